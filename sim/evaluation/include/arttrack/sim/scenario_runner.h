// Runs a scenario: simulates the robot, corrupts its sensors, feeds every
// tracking method the same corrupted data in lockstep and scores each against
// the ground truth.
//
// Per run k (seed run_seed(scenario seed, k)): one simulator with the
// PERTURBED URDF (miscalibration, model mismatch; with model_mismatch.random
// the robot drawn for run k, run_model_error), one Tracker per method
// built on the NOMINAL URDF, in synchronous mode. Trackers never see ground
// truth: they get corrupted encoder readings at the joint rate and corrupted
// depth images, stamped with their capture time, at their arrival time
// (latency, jitter, drops). Only vision_only gets the true initial
// configuration (its starting point is "given", as in the paper).
//
// Scoring (scoring.h, paper Sec. V): at every camera capture time (and every
// N joint steps if the scenario says so), each scored end effector's pose in
// the method's estimated camera frame against its true pose in the true
// camera frame; per joint, estimated minus true angle and bias (true bias:
// EncoderCorruption::bias_rad()); the estimated camera frame (the nominal
// model's forward kinematics at the estimated angles and camera offset)
// against the simulator's true camera, both relative to the robot base; and
// the reported standard deviations against these errors (consistency).
//
// The runner simulates and measures; what it gives (RunResult,
// ScenarioResult) and the stream a MeasurementSink sees are run_result.h;
// feeding the trackers, scoring their estimates and keeping frames is
// method_trackers.h, shared with `arttrack track` (dataset_tracking.h).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "arttrack/sim/run_result.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/sim_model.h"

namespace arttrack::sim {

// Where a run is, for progress reports.
struct RunProgress {
  int run = 0;   // 0-based
  int runs = 1;  // total
  double time_s = 0;
  double duration_s = 0;
};

struct RunOptions {
  // Number of runs (0: the scenario's `runs`).
  int runs = 0;
  // The scenario seed that run seeds derive from (-1: the scenario's `seed`).
  long long seed = -1;
  // Methods to run (empty: the scenario's `methods`).
  std::vector<std::string> methods;
  // Called about every simulated second (may be empty).
  std::function<void(const RunProgress&)> progress;
  // Depth frames kept for reports, evenly spread over run 0.
  int frames_to_keep = 4;
  // Sees every run's measurements and truth (may be null; not owned).
  MeasurementSink* sink = nullptr;
  // Depth delivered in whole millimetres, as a 16-bit PNG stores it
  // (quantise_depth_mm in depth_png.h): a run then equals tracking its
  // exported dataset.
  bool quantise_depth_mm = false;
  // Real time: each run is simulated first and its measurements kept (at
  // most 4 GB, 110 s of a 640x480 camera; a longer run is refused before it
  // starts), then replayed: each joint step waits until its simulated time
  // has passed on the wall clock since the replay began, and the trackers
  // are asynchronous (TrackerConfig::asynchronous): image updates run on
  // their own threads while joint readings go on, as on a robot; images that
  // arrive while an update runs wait or are dropped (TrackerStats). Image
  // latencies are then measured (MethodRun::image_latency_ms). Simulating
  // first keeps the simulator's physics and full-mesh rendering off the
  // cores the trackers use, as a robot's camera is.
  bool realtime = false;
};

// The seed of run k of a scenario with seed `seed`: a SplitMix64 mix (so
// neighbouring runs get unrelated streams) cut to 53 bits (exact in JSON).
std::uint64_t run_seed(std::uint64_t seed, int run);

// The joint targets the simulator's servos follow in run `run` of
// `scenario` with seed `seed` (the scenario's `seed`, or --seed), for the
// joints of `model`: the motion run_scenario drives that run with.
JointTrajectory run_trajectory(const Scenario& scenario, const SimModel& model, std::uint64_t seed,
                               int run);

// The robot run `run` of `scenario` with seed `seed` simulates: the
// scenario's model_mismatch and, under model_mismatch.random, that run's
// draw (what run_scenario builds that run's simulator from).
DrawnModelError run_robot(const Scenario& scenario, std::uint64_t seed, int run);

// Runs the scenario. Throws InputError for bad options (unknown method,
// runs < 1) or a scenario the simulator or tracker rejects.
ScenarioResult run_scenario(const Scenario& scenario, const RunOptions& options = {});

}  // namespace arttrack::sim
