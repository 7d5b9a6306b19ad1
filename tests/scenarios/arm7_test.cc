// The second robot (models/arm7.urdf, scenarios/arm7/): a single arm with a
// mimic finger, no inertials and a camera the scene mounts in the world.
// Full fusion must track it clearly better than the encoders alone over
// three seeds of the constant-bias scenario, never lose it, and keep its
// camera offset off the motion its round base hides. Short runs
// (short_run.h: 160x120 camera, 80x60 likelihood; about 14 s, label slow).
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
    // 162.2, 160.1 mm; full fusion p50 0.06, 0.06, 0.06 mm, p99 0.61, 0.46,
    // 0.47 mm (stop 98; 7.6 mm when this test was written, issue 12; with
    // refinement.unseen_information_ratio 0, p99 0.50, 0.37, 0.53 mm).
    EXPECT_GT(encoders.p50, 80 * kMm);
    EXPECT_LT(fusion.p50, 1 * kMm);
    EXPECT_LT(fusion.p50, encoders.p50 / 8);
    EXPECT_LT(fusion.p99, 5 * kMm);
    const MethodResult& fusion_result = method(r, "full_fusion");
    EXPECT_EQ(fusion_result.summary.lost_runs(), 0u);
    // The base link is two coaxial cylinders: the camera orbiting its axis
    // while joint 1 turns back moves no surface, so the camera offset must
    // stay where its prior puts it along that motion. Measured (seeds 1, 2,
    // 3) from 10 to 12 s: camera p50 1.4, 1.1, 2.2 mm and 0.04, 0.03, 0.06
    // degrees, every image (361 of 361) counted as holding such a motion;
    // with refinement.unseen_information_ratio 0 (the central differences
    // read the base's edges as information there and the step walked the
    // camera along it) 43.8, 27.2, 32.2 mm and 1.32, 0.82, 0.97 degrees
    // (docs/accuracy.md, "Directions that move no surface").
    EXPECT_LT(fusion_result.summary.converged.camera_translation_m.p50, 10 * kMm);
    EXPECT_LT(fusion_result.summary.converged.camera_rotation_rad.p50, 0.3 * kRadPerDeg);
    EXPECT_GT(fusion_result.counts.images_with_unseen_motion, 300);
    // The finger is the one prismatic joint: its figures are metres.
    ASSERT_EQ(r.prismatic.size(), r.joint_names.size());
    for (std::size_t j = 0; j < r.joint_names.size(); ++j)
      EXPECT_EQ(r.is_prismatic(j), r.joint_names[j] == "arm7_finger_joint1") << r.joint_names[j];
  }
}

}  // namespace
}  // namespace arttrack::sim::test
