// The second robot (models/arm7.urdf, scenarios/arm7/): a single arm with a
// mimic finger, no inertials and a camera the scene mounts in the world.
// Full fusion must track it clearly better than the encoders alone over
// three seeds of the constant-bias scenario, and never lose it. Short runs
// (short_run.h: 160x120 camera, 80x60 likelihood; about 21 s, label slow).
//
// Thresholds from measured values with a margin; the measured values are in
// the comments.
#include <gtest/gtest.h>

#include <string>

#include "short_run.h"

namespace arttrack::sim::test {
namespace {

TEST(Arm7, FullFusionTracksTheSecondRobotBetterThanEncodersOverThreeSeeds) {
  for (const int seed : {1, 2, 3}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const ScenarioResult r = run_short("arm7/constant_bias", 12, {"encoders_only", "full_fusion"},
                                       {"seed=" + std::to_string(seed)});
    const Percentiles encoders = window(r, "encoders_only", 6, 12);
    const Percentiles fusion = window(r, "full_fusion", 6, 12);
    // Measured (seeds 1, 2, 3) from 6 to 12 s: encoders only p50 158.9,
    // 162.2, 160.1 mm; full fusion p50 0.06, 0.05, 0.05 mm, p99 0.50, 0.37,
    // 0.53 mm (stop 98; 7.6 mm when this test was written, issue 12).
    EXPECT_GT(encoders.p50, 80 * kMm);
    EXPECT_LT(fusion.p50, 1 * kMm);
    EXPECT_LT(fusion.p50, encoders.p50 / 8);
    EXPECT_LT(fusion.p99, 5 * kMm);
    EXPECT_EQ(method(r, "full_fusion").summary.lost_runs(), 0u);
    // The finger is the one prismatic joint: its figures are metres.
    ASSERT_EQ(r.prismatic.size(), r.joint_names.size());
    for (std::size_t j = 0; j < r.joint_names.size(); ++j)
      EXPECT_EQ(r.is_prismatic(j), r.joint_names[j] == "arm7_finger_joint1") << r.joint_names[j];
  }
}

}  // namespace
}  // namespace arttrack::sim::test
