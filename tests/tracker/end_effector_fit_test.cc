// EndEffectorFit (end_effector_fit.h): which link each end effector's fit
// moves, when it is on, and how an image's fit becomes a correction.
#include "arttrack/tracker/internal/end_effector_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "arttrack/tracker/kinematics.h"
#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)

// The tool has no geometry: its fit moves the forearm ("lower"). The base
// carries the camera: a fit there would move the camera, the camera
// offset's to correct, so an end effector at the base is not fitted.
TEST(EndEffectorFit, FitsTheNearestLinkWithGeometryTheCameraDoesNotHangFrom) {
  TrackerConfig config = small_config(TrackingMethod::kFullFusion);
  config.end_effectors = {"tool", "base_link"};
  const TrackerSetup setup(arm_model(), config, {"shoulder", "elbow"});
  const EndEffectorFit fit(setup);
  EXPECT_TRUE(fit.on());
  EXPECT_EQ(fit.fit_links(), std::vector<int>{setup.model->link_index("lower")});
  EXPECT_EQ(fit.corrections().size(), 2u);
}

TEST(EndEffectorFit, OnlyFullFusionWithTheOptionFits) {
  for (TrackingMethod m : {TrackingMethod::kEncodersOnly, TrackingMethod::kCameraOffsetOnly,
                           TrackingMethod::kVisionOnly}) {
    const TrackerSetup setup(arm_model(), small_config(m), {"shoulder", "elbow"});
    EXPECT_FALSE(EndEffectorFit(setup).on());
  }
  TrackerConfig config = small_config(TrackingMethod::kFullFusion);
  config.end_effector_fit.enabled = false;
  const TrackerSetup setup(arm_model(), config, {"shoulder", "elbow"});
  EXPECT_FALSE(EndEffectorFit(setup).on());
}

// A fit that moves the forearm 3 mm along the camera's z, at a mean the
// refinement then did not move: after one time constant the correction is
// 1 - 1/e of that motion, in the tool's axes; a fit the image barely
// determines (translation sd 1 cm, above max_std_m) changes nothing.
TEST(EndEffectorFit, AveragesWellDeterminedFitsInTheToolsAxes) {
  const TrackerSetup setup(arm_model(), small_config(TrackingMethod::kFullFusion),
                           {"shoulder", "elbow"});
  EndEffectorFit fit(setup);
  const std::vector<double> mean(std::size_t(setup.n), 0.0);
  ImageInformation::RigidFit seen;
  seen.information = Eigen::Matrix<double, 6, 6>::Identity() * 1e8;  // sd 0.1 mm
  seen.gradient.head<3>() = Eigen::Vector3d(0, 0, 0.003) * 1e8;
  seen.pixels = 100;
  ImageInformation::RigidFit vague = seen;
  vague.information = Eigen::Matrix<double, 6, 6>::Identity() * 1e4;  // sd 1 cm
  vague.gradient.head<3>() = Eigen::Vector3d(0.05, 0, 0) * 1e4;
  fit.update(0.0, {seen}, mean, mean);  // starts the clock: no weight yet
  fit.update(1.0, {seen}, mean, mean);
  const std::vector<EndEffectorCorrection> after_one = fit.corrections();
  fit.update(2.0, {vague}, mean, mean);
  EXPECT_EQ(fit.corrections()[0], after_one[0]);

  KinematicsState state(*setup.model);
  forward_kinematics(*setup.model, Eigen::VectorXd::Zero(setup.n), state);
  const Eigen::Matrix3d R_camera_tool =
      T_camera_link(*setup.model, state, setup.model->link_index("tool")).linear();
  const Eigen::Vector3d expected =
      (1 - std::exp(-1.0)) * R_camera_tool.transpose() * Eigen::Vector3d(0, 0, 0.003);
  EXPECT_LT((after_one[0].head<3>() - expected).norm(), 1e-9);
  EXPECT_LT(after_one[0].tail<3>().norm(), 1e-12);
}

}  // namespace
}  // namespace arttrack
