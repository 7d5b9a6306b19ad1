// An arm behind an occluder stays where the encoders and its learned biases
// put it (issue 28): in scenarios/occlusion.yaml a board sweeps in front of
// the moving left arm from 12 s on, a few centimetres from its surfaces, so
// the health check finds the hand unexplained (unconfirmed) and searches it
// again. Before confirming searches had to be confirmed by the image, the
// search took an arm tucked behind the board or laid over it: on both the
// primitive and the sculpted dual arm, at the scenario's own 640x480
// camera, the left hand went 420-470 mm off at 15.0 s and stayed there for
// the rest of the run (lost). About 60 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "short_run.h"

namespace arttrack::sim::test {
namespace {

TEST(Occlusion, AnArmBehindTheBoardStaysOnBothRobots) {
  for (const char* scenario : {"occlusion", "sculpted/occlusion"}) {
    SCOPED_TRACE(scenario);
    const ScenarioResult r =
        run_short(scenario, 18, {"full_fusion"}, {"camera.width=640", "camera.height=480"});
    EXPECT_EQ(method(r, "full_fusion").summary.lost_runs(), 0u);
    const MethodRun& fusion = r.runs.at(0).methods.at(0);
    ASSERT_EQ(r.end_effectors.at(0), "left_ee");
    double worst_hidden_m = 0;
    for (std::size_t i = 0; i < fusion.samples.size(); ++i)
      if (r.runs[0].truth[i].time_s >= 12)
        worst_hidden_m = std::max(worst_hidden_m, fusion.samples[i].ee_error.at(0).translation_m);
    std::cout << scenario << ": left hand worst from 12 s " << worst_hidden_m / kMm << " mm\n";
    // Measured: 14.8 mm (primitives) and 21.0 mm (sculpted; 29.4 mm while
    // the first image's search moved the camera, before stop 47) at worst;
    // the reported standard deviations of the two elbow joints grow to
    // 1.5-2 degrees meanwhile, and cover those errors.
    EXPECT_LT(worst_hidden_m, 60 * kMm);
  }
}

// Issue 28's third target on both shipped robots and several seeds: while
// the board passes in front of the arm (from 12 s; arm7/occlusion.yaml's
// across arm7's one arm, occlusion.yaml's across the dual arm's left; on
// seed 2 it hides up to 42% and 34% of the robot's pixels between 13 and
// 18 s), the hand's error stays far below the encoders' alone, and no run
// is lost. Short runs (160x120, the 80x60 likelihood), seeds other than
// the files' own. About 60 s.
TEST(Occlusion, TheHandBehindTheBoardBeatsTheEncodersOnBothRobotsOverSeeds) {
  for (const char* scenario : {"arm7/occlusion", "occlusion"}) {
    for (const int seed : {2, 3, 4}) {
      SCOPED_TRACE(std::string(scenario) + " seed " + std::to_string(seed));
      const ScenarioResult r = run_short(scenario, 18, {"encoders_only", "full_fusion"},
                                         {"seed=" + std::to_string(seed)});
      const Percentiles encoders = window(r, "encoders_only", 12, 18);
      const Percentiles fusion = window(r, "full_fusion", 12, 18);
      // Measured from 12 to 18 s (the worse hand per sample), p99 over seeds
      // 2, 3, 4: arm7 full fusion 1.2, 1.6, 0.9 mm, encoders only 172.4,
      // 185.2, 177.1 mm; the dual arm 6.2, 6.0, 5.9 mm against 249.8, 248.2,
      // 255.0 mm. Before searches had to be confirmed by the image, one took
      // the hidden arm 420-470 mm off (the test above).
      EXPECT_EQ(method(r, "full_fusion").summary.lost_runs(), 0u);
      EXPECT_LT(fusion.p99, 20 * kMm);
      EXPECT_LT(fusion.p99, encoders.p99 / 8);
    }
  }
}

}  // namespace
}  // namespace arttrack::sim::test
