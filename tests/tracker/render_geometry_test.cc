// RenderGeometry (tracker/internal): the robot drawn for a camera, and the
// score of one configuration against an image.
#include "arttrack/tracker/internal/render_geometry.h"

#include <gtest/gtest.h>

#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)

// The score is beta log p(z | r(q)) / p(z | no robot) of the robot drawn at
// q: the same number as rendering it by hand; the truth scores best.
TEST(RenderGeometry, ScoreIsTheTemperedLogRatioOfTheRobotDrawnAtQ) {
  const auto model = arm_model();
  TrackerConfig::Geometry full;
  full.max_error_px = 0;  // the model's own meshes
  RenderGeometry geometry(model, full);
  EXPECT_FALSE(geometry.has_camera(kCamera));
  EXPECT_TRUE(geometry.use_camera(kCamera));
  EXPECT_TRUE(geometry.has_camera(kCamera));
  EXPECT_EQ(&geometry.drawn_model(), model.get());
  EXPECT_LE(geometry.error_bound_m(), 0.0);

  DepthModelParams pixels;
  pixels.width = kCamera.width;
  pixels.height = kCamera.height;
  DepthLikelihood likelihood(pixels);
  likelihood.set_observation(render_truth(*model, 0.4, -0.6));
  std::vector<double> q(std::size_t(model->num_joints()), 0.0);
  q[std::size_t(model->joint_index("shoulder"))] = 0.3;
  q[std::size_t(model->joint_index("elbow"))] = -0.6;
  const double beta = 0.25;
  const double expected = beta * likelihood.log_ratio(render_truth(*model, 0.3, -0.6));
  EXPECT_EQ(geometry.score(q, likelihood, beta), expected);
  q[std::size_t(model->joint_index("shoulder"))] = 0.4;
  EXPECT_GT(geometry.score(q, likelihood, beta), expected);
}

// geometry.open_parts_both_sides reaches the renderers: the geometry's own
// and, through render_options(), the evaluators' (image_filter.cc,
// acquisition.cc).
TEST(RenderGeometry, OpenPartsBothSidesReachesTheRenderers) {
  for (const bool both_sides : {false, true}) {
    TrackerConfig::Geometry params;
    params.open_parts_both_sides = both_sides;
    RenderGeometry geometry(arm_model(), params);
    ASSERT_TRUE(geometry.use_camera(kCamera));
    EXPECT_EQ(geometry.render_options().open_parts_both_sides, both_sides);
    EXPECT_EQ(geometry.renderer().options().open_parts_both_sides, both_sides);
  }
}

// Simplified meshes are made once per model and bound and shared; a camera
// at the same bound keeps the drawn model (only the renderer is new).
TEST(RenderGeometry, SimplifiedModelsAreSharedPerModelAndBound) {
  const auto model = arm_model();
  double error_a = -1, error_b = -1;
  const auto a = simplified_model(model, 0.002, 0.3, 4, error_a);
  const auto b = simplified_model(model, 0.002, 0.3, 4, error_b);
  EXPECT_EQ(a, b);
  EXPECT_EQ(error_a, error_b);
  double error_c = -1;
  EXPECT_NE(simplified_model(model, 0.004, 0.3, 4, error_c), a);
  EXPECT_NE(simplified_model(arm_model(), 0.002, 0.3, 4, error_c), a);

  RenderGeometry geometry(model, TrackerConfig::Geometry{});
  ASSERT_TRUE(geometry.use_camera(kCamera));
  EXPECT_GT(geometry.error_bound_m(), 0.0);
  const RobotModel* drawn = &geometry.drawn_model();
  EXPECT_NE(drawn, model.get());
  EXPECT_FALSE(geometry.use_camera(kCamera));  // same bound: the same drawn model
  EXPECT_EQ(&geometry.drawn_model(), drawn);
  const CameraIntrinsics finer = CameraIntrinsics::from_vertical_fov(128, 96, 60 * kRadPerDeg);
  EXPECT_FALSE(geometry.has_camera(finer));
  EXPECT_TRUE(geometry.use_camera(finer));  // a finer pixel: a tighter bound
  EXPECT_LT(geometry.error_bound_m(), TrackerConfig::Geometry{}.error_bound_m(kCamera));
}

}  // namespace
}  // namespace arttrack
