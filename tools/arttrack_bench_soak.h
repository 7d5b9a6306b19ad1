// arttrack bench --soak MINUTES: the tracker's memory over a long stream.
#pragma once

#include <memory>

#include "arttrack/sim/scenario.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack::cli {

struct SoakOptions {
  double minutes = 60;       // simulated stream
  int frames = 30;           // distinct depth images, rendered once and reused
  double max_growth_mb = 1;  // allowed resident growth from minute 1 to the end
  long long seed = -1;       // scenario seed of the recorded stream (-1: the scenario's)
};

// Records `frames` depth images (30 Hz) and the encoder readings (1 kHz) of
// the scenario's run 0, then feeds one synchronous tracker (`config`) that
// recording over and over, time stamps advancing, for `minutes` of stream as
// fast as it can. Prints the resident memory (VmRSS) after one simulated
// minute, every ten minutes and at the end; throws InputError (exit 1) when
// it grew by more than max_growth_mb from minute one to the end.
void run_soak(sim::Scenario scenario, std::shared_ptr<const RobotModel> robot,
              const TrackerConfig& config, const SoakOptions& options);

}  // namespace arttrack::cli
