// Refinement (tracker/internal): the Gauss-Newton step on the mean after an
// image's particle filter.
#include "arttrack/tracker/internal/refinement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

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

// The planar arm at its true angles with the camera's depth offset
// `offset_m` off the image, under a prior of `initial_std_m` around it; the
// reported covariance has begun the image.
struct DepthOffsetScene {
  DepthOffsetScene(double offset_m, double initial_std_m, double widen_beyond_sigma)
      : config(scene_config(initial_std_m, widen_beyond_sigma)),
        setup(arm_model(), config, {"shoulder", "elbow"}),
        depth(setup.model->joint_index("camera_offset_z")),
        image(setup),
        reported(setup, image.filter().blocks()),
        refinement(setup, reported.setup().states) {
    image.set_image(render_truth(*setup.model, 0.4, -0.6), kCamera);
    std::vector<double> reading(2, 0.0);
    reading[std::size_t(setup.model->joint_index("shoulder"))] = 0.4;
    reading[std::size_t(setup.model->joint_index("elbow"))] = -0.6;
    belief = initial_joint_belief(*setup.filter_model, reading);
    belief.mean_a[std::size_t(depth)] = offset_m;
    for (double v : belief.var_a) prior_std.push_back(std::sqrt(v));
    prior_mean = belief.mean_a;
    std::vector<char> reopened(std::size_t(setup.n), 0);
    begun = reported.begin_image(0.0, prior_std, reopened, belief.mean_a,
                                 image.geometry().renderer(), image.likelihood());
  }
  static TrackerConfig scene_config(double initial_std_m, double widen_beyond_sigma) {
    TrackerConfig c = small_config(TrackingMethod::kFullFusion);
    c.camera_translation.initial_std = initial_std_m;
    c.refinement_widen_beyond_sigma = widen_beyond_sigma;
    return c;
  }
  // The refinement with `spread` as the particles' spread.
  bool refine(std::span<const double> spread) {
    return refinement.refine(reported.covariance(), reported.information(), prior_mean, spread,
                             image, belief);
  }
  double depth_offset_m() const { return belief.mean_a[std::size_t(depth)]; }

  TrackerConfig config;
  TrackerSetup setup;
  int depth;
  ImageFilter image;
  ReportedCovariance reported;
  Refinement refinement;
  JointBelief belief;
  std::vector<double> prior_std, prior_mean;
  bool begun = false;
};

// The camera's depth offset 4 mm off the image, with a broad prior around
// it: the step moves it towards the image, and only the angle means change.
TEST(Refinement, StepMovesAMeanOffTheImageTowardsIt) {
  DepthOffsetScene scene(0.004, 0.02, 2.0);
  ASSERT_TRUE(scene.begun);
  const JointBelief before = scene.belief;
  ASSERT_TRUE(scene.refine(scene.prior_std));
  EXPECT_LT(std::abs(scene.depth_offset_m()), 0.002);
  EXPECT_EQ(scene.belief.var_a, before.var_a);
  // The step raised the target, so the image prefers the new mean.
  EXPECT_GT(scene.image.score(scene.belief.mean_a), scene.image.score(before.mean_a));
}

// The camera's depth offset 8 mm off the image under a 3 mm prior, and the
// particles' spread collapsed to 0.1 mm, as within an image or two of the
// first: the step (about 2.7 reported standard deviations) moves up to the
// reported 3 mm when refinement.widen_beyond_sigma allows it, and only the
// spread when it is 0.
TEST(Refinement, AStepFarBeyondTheReportedSpreadWidensTheTrustRegion) {
  auto moved_m = [](double widen_beyond_sigma) {
    DepthOffsetScene scene(0.008, 0.003, widen_beyond_sigma);
    EXPECT_TRUE(scene.begun);
    const std::vector<double> collapsed(scene.prior_std.size(), 1e-4);
    EXPECT_TRUE(scene.refine(collapsed));
    return 0.008 - scene.depth_offset_m();
  };
  const double widened_m = moved_m(2.0);
  const double crawled_m = moved_m(0.0);
  EXPECT_GT(crawled_m, 0.0);
  EXPECT_LE(crawled_m, 1e-4 + 1e-9);
  EXPECT_GT(widened_m, 1.4e-3);
  EXPECT_LE(widened_m, 3e-3 + 1e-9);
}

}  // namespace
}  // namespace arttrack
