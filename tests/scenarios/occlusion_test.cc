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

}  // namespace
}  // namespace arttrack::sim::test
