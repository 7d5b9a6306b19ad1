// Refinement (tracker/internal): the Gauss-Newton step on the mean after an
// image's particle filter.
#include "arttrack/tracker/internal/refinement.h"

#include <gtest/gtest.h>

#include <cmath>

#include "arttrack/tracker/internal/reported_covariance.h"
#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)

TEST(Refinement, OnlyFullFusionWithRefineMeanRefines) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  const TrackerSetup fusion(arm_model(), c, {"shoulder", "elbow"});
  EXPECT_TRUE(Refinement(fusion, {}).on());
  c.refine_mean = false;
  EXPECT_FALSE(Refinement(TrackerSetup(arm_model(), c, {"shoulder", "elbow"}), {}).on());
  c = small_config(TrackingMethod::kCameraOffsetOnly);
  EXPECT_FALSE(Refinement(TrackerSetup(arm_model(), c, {"shoulder", "elbow"}), {}).on());
}

// The camera's depth offset 4 mm off the image, with a broad prior around
// it: the step moves it towards the image, and only the angle means change.
TEST(Refinement, StepMovesAMeanOffTheImageTowardsIt) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.camera_translation.initial_std = 0.02;
  const TrackerSetup setup(arm_model(), c, {"shoulder", "elbow"});
  const int shoulder = setup.model->joint_index("shoulder");
  const int elbow = setup.model->joint_index("elbow");
  const int depth = setup.model->joint_index("camera_offset_z");
  ImageFilter image(setup);
  image.set_image(render_truth(*setup.model, 0.4, -0.6), kCamera);
  ReportedCovariance reported(setup, image.filter().blocks());
  Refinement refinement(setup, reported.setup().states);

  std::vector<double> reading(2, 0.0);
  reading[std::size_t(shoulder)] = 0.4;
  reading[std::size_t(elbow)] = -0.6;
  JointBelief belief = initial_joint_belief(*setup.filter_model, reading);
  belief.mean_a[std::size_t(depth)] = 0.004;
  std::vector<double> prior_std;
  for (double v : belief.var_a) prior_std.push_back(std::sqrt(v));
  const std::vector<double> prior_mean = belief.mean_a;
  std::vector<char> reopened(std::size_t(setup.n), 0);
  ASSERT_TRUE(reported.begin_image(0.0, prior_std, reopened, belief.mean_a,
                                   image.geometry().renderer(), image.likelihood()));
  const JointBelief before = belief;
  ASSERT_TRUE(refinement.refine(reported.covariance(), reported.information(), prior_mean,
                                prior_std, image, belief));
  EXPECT_LT(std::abs(belief.mean_a[std::size_t(depth)]), 0.002);
  EXPECT_EQ(belief.var_a, before.var_a);
  // The step raised the target, so the image prefers the new mean.
  EXPECT_GT(image.score(belief.mean_a), image.score(before.mean_a));
}

}  // namespace
}  // namespace arttrack
