// EndEffectorFit (end_effector_fit.h): which link each end effector's fit
// moves, when it is on, and how an image's fit becomes a correction.
#include "arttrack/tracker/internal/end_effector_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

#include "arttrack/tracker/kinematics.h"
#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)

// The tool's rotation in the camera at the zero configuration: the
// corrections' and covariances' axes.
Eigen::Matrix3d R_camera_tool(const TrackerSetup& setup) {
  KinematicsState state(*setup.model);
  forward_kinematics(*setup.model, Eigen::VectorXd::Zero(setup.n), state);
  return T_camera_link(*setup.model, state, setup.model->link_index("tool")).linear();
}

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
  EXPECT_EQ(fit.estimates().size(), 2u);
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
// determines (translation sd 1 cm, above max_std_m) leaves the average,
// and the reported correction fades while no image shows the hand.
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
  fit.update(0.0, {seen}, mean, mean, 0.0);  // starts the clock: no weight yet
  EXPECT_EQ(fit.estimates()[0].weight, 0.0);
  fit.update(1.0, {seen}, mean, mean, 0.0);
  std::vector<EndEffectorCorrection> after_one;
  for (const EndEffectorFitEstimate& e : fit.estimates()) after_one.push_back(e.correction);
  const Eigen::Vector3d sample = R_camera_tool(setup).transpose() * Eigen::Vector3d(0, 0, 0.003);
  const double w = 1 - std::exp(-1.0);  // an image 1 s after the last, time constant 1 s
  EXPECT_LT((after_one[0].head<3>() - w * sample).norm(), 1e-9);
  EXPECT_LT(after_one[0].tail<3>().norm(), 1e-12);

  // An image too vague to count, 1 s after the last that showed the hand:
  // the correction fades by exp(-1) towards none; the next image that
  // shows it averages with the correction before the fade.
  fit.update(2.0, {vague}, mean, mean, 0.0);
  EXPECT_LT((fit.estimates()[0].correction - std::exp(-1.0) * after_one[0]).norm(), 1e-15);
  fit.update(3.0, {seen}, mean, mean, 0.0);
  const Eigen::Vector3d resumed = w * sample + w * (sample - w * sample);
  EXPECT_LT((fit.estimates()[0].correction.head<3>() - resumed).norm(), 1e-9);
}

// The corrected position's uncertainty (end_effector_fit.h): the fits'
// exponentially weighted scatter about their average, over the fits' total
// weight, plus the shape error's shift in every direction, in the tool's
// axes, at the unpinned scale (2) in every direction here, where the fits
// determine every direction alike (the test below has one that they do
// not). Fits alternating between two places 2 mm apart along the camera's
// x: by hand, West's weighted variance; fits too vague to count leave the
// covariance and fade the fits' say by exp(-t / time constant), t the time
// since the last fit that counted; the same fit every image shrinks the
// scatter, not the shape error, and gives the say back.
TEST(EndEffectorFit, PositionCovarianceIsTheFitsScatterPlusTheShapeError) {
  const TrackerSetup setup(arm_model(), small_config(TrackingMethod::kFullFusion),
                           {"shoulder", "elbow"});
  EndEffectorFit fit(setup);
  const std::vector<double> mean(std::size_t(setup.n), 0.0);
  const Eigen::Matrix3d R = R_camera_tool(setup);

  auto fit_at = [](double x_m) {
    ImageInformation::RigidFit f;
    f.information = Eigen::Matrix<double, 6, 6>::Identity() * 1e8;  // sd 0.1 mm
    f.gradient.head<3>() = Eigen::Vector3d(x_m, 0, 0) * 1e8;
    f.pixels = 100;
    return f;
  };
  const double shape_std_m = 0.0015, dt_s = 0.1, w = 1 - std::exp(-dt_s);  // time constant 1 s
  fit.update(0.0, {fit_at(0.001)}, mean, mean, shape_std_m);               // starts the clock
  EXPECT_EQ(fit.estimates()[0].weight, 0.0);
  Eigen::Vector3d average = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double weight = 0;
  for (int k = 1; k <= 20; ++k) {
    const Eigen::Vector3d sample = R.transpose() * Eigen::Vector3d(k % 2 ? 0.002 : 0.0, 0, 0);
    fit.update(k * dt_s, {fit_at(k % 2 ? 0.002 : 0.0)}, mean, mean, shape_std_m);
    const Eigen::Vector3d deviation = sample - average;
    scatter = (1 - w) * (scatter + w * deviation * deviation.transpose());
    average += w * deviation;
    weight += w * (1 - weight);
  }
  const EndEffectorFitEstimate after = fit.estimates()[0];
  EXPECT_NEAR(after.weight, weight, 1e-12);
  EXPECT_NEAR(after.weight, 1 - std::exp(-20 * dt_s), 1e-12);
  const double scale = setup.config.model_error_unpinned_scale;  // the shape error's, all axes
  const double shape_var_m2 = scale * scale * shape_std_m * shape_std_m;
  const Eigen::Matrix3d expected = scatter / weight + shape_var_m2 * Eigen::Matrix3d::Identity();
  EXPECT_LT((after.position_covariance_m2 - expected).norm(), 1e-12);
  // About the alternation's variance (1 mm)^2 along the camera's x, the
  // shape error's elsewhere.
  const Eigen::Matrix3d camera_axes = R * after.position_covariance_m2 * R.transpose();
  EXPECT_NEAR(camera_axes(0, 0), 1e-6 + shape_var_m2, 0.5e-6);
  EXPECT_NEAR(camera_axes(1, 1), shape_var_m2, 1e-12);

  ImageInformation::RigidFit vague = fit_at(0.05);
  vague.information *= 1e-4;  // sd 1 cm: above max_std_m
  fit.update(2.1, {vague}, mean, mean, shape_std_m);
  EXPECT_NEAR(fit.estimates()[0].weight, after.weight * std::exp(-dt_s), 1e-15);  // fades
  fit.update(2.5, {vague}, mean, mean, shape_std_m);
  EXPECT_NEAR(fit.estimates()[0].weight, after.weight * std::exp(-0.5), 1e-15);  // since 2.0 s
  EXPECT_EQ(fit.estimates()[0].position_covariance_m2, after.position_covariance_m2);
  EXPECT_LT((fit.estimates()[0].correction - std::exp(-0.5) * after.correction).norm(), 1e-15);

  for (int k = 26; k <= 120; ++k) fit.update(k * dt_s, {fit_at(0.001)}, mean, mean, shape_std_m);
  const Eigen::Matrix3d settled = R * fit.estimates()[0].position_covariance_m2 * R.transpose();
  EXPECT_LT(settled(0, 0) - shape_var_m2, 0.01e-6);
  EXPECT_GE(settled(0, 0), shape_var_m2);
  EXPECT_GT(fit.estimates()[0].weight, 0.9999);
}

// A hand the image shows well across but hardly along one direction (the
// camera's z here: translation sd 0.1 mm in x and y, 1 mm in z): the
// same fit every image, so no scatter. The shape error is sigma^2 in
// every direction plus (2^2 - 1) sigma^2 times the fits' noise shape
// (largest eigenvalue 1): 4 sigma^2 along z, sigma^2 (1 + 3 * 0.01)
// across, in the camera's axes; with the unpinned scale at 1, sigma^2
// everywhere.
TEST(EndEffectorFit, TheLeastDeterminedDirectionCarriesTheUnpinnedShapeError) {
  for (const double scale : {2.0, 1.0}) {
    TrackerConfig config = small_config(TrackingMethod::kFullFusion);
    config.model_error_unpinned_scale = scale;
    const TrackerSetup setup(arm_model(), config, {"shoulder", "elbow"});
    EndEffectorFit fit(setup);
    const std::vector<double> mean(std::size_t(setup.n), 0.0);
    const Eigen::Matrix3d R = R_camera_tool(setup);
    ImageInformation::RigidFit f;
    f.information = Eigen::Matrix<double, 6, 6>::Identity() * 1e8;
    f.information(2, 2) = 1e6;
    f.pixels = 100;  // no motion: no scatter
    const double shape_std_m = 0.0015, var = shape_std_m * shape_std_m;
    for (int k = 0; k <= 100; ++k) fit.update(0.1 * k, {f}, mean, mean, shape_std_m);
    const Eigen::Matrix3d camera_axes =
        R * fit.estimates()[0].position_covariance_m2 * R.transpose();
    const double extra = scale * scale - 1;
    EXPECT_NEAR(camera_axes(2, 2), var * (1 + extra), 1e-12) << scale;
    EXPECT_NEAR(camera_axes(0, 0), var * (1 + extra * 0.01), 1e-12) << scale;
    EXPECT_NEAR(camera_axes(1, 1), var * (1 + extra * 0.01), 1e-12) << scale;
    EXPECT_NEAR(camera_axes(0, 2), 0.0, 1e-15) << scale;
  }
}

// end_effector_fit.link_scales: a fitted link the images learned to be 4%
// larger than its model moves every fit by 0.04 times the fit's response
// to its scale, here 1.5 mm along the camera's x at the tool (the
// response a pure translation, the fit isotropic): the same in every
// image, so once the fits' say is whole it is all of the added
// covariance, along x alone. Not learned (NaN), or the option off: none.
TEST(EndEffectorFit, LearnedLinkScalesWidenTheFittedPositionByTheirShift) {
  for (const bool on : {true, false}) {
    TrackerConfig config = small_config(TrackingMethod::kFullFusion);
    config.end_effector_fit.link_scales = on;
    const TrackerSetup setup(arm_model(), config, {"shoulder", "elbow"});
    for (const double scale : {0.04, std::numeric_limits<double>::quiet_NaN()}) {
      EndEffectorFit fit(setup);
      const std::vector<double> mean(std::size_t(setup.n), 0.0);
      const Eigen::Matrix3d R = R_camera_tool(setup);
      ImageInformation::RigidFit f;
      f.information = Eigen::Matrix<double, 6, 6>::Identity() * 1e8;
      f.pixels = 100;  // no motion: no scatter
      f.scale_links = {1};
      f.scale_cross.setZero(6, 1);
      f.scale_cross(0, 0) = 1e8 * 0.0015 / 0.04;  // information^-1 of it: 1.5 mm / 4%
      const std::vector<double> link_scales = {0.0, scale, 0.0};
      for (int k = 0; k <= 200; ++k) fit.update(0.1 * k, {f}, mean, mean, 0.0, {}, link_scales);
      const Eigen::Matrix3d camera_axes =
          R * fit.estimates()[0].position_covariance_m2 * R.transpose();
      const double expected_m2 = on && !std::isnan(scale) ? 0.0015 * 0.0015 : 0.0;
      EXPECT_NEAR(camera_axes(0, 0), expected_m2, 1e-6 * 0.0015 * 0.0015) << on << scale;
      EXPECT_NEAR(camera_axes(1, 1), 0.0, 1e-15);
      EXPECT_NEAR(camera_axes(2, 2), 0.0, 1e-15);
    }
  }
}

// uncertainty.depth_scale_std s: a depth scale off by s puts the fitted
// hand s times its distance away along its line of sight, in every image:
// s^2 X X^T (X the tool's position in camera axes, 1.04 m away) with no
// scatter and no shape error, all of it along the line of sight.
TEST(EndEffectorFit, AStatedDepthScaleWidensTheLineOfSight) {
  TrackerConfig config = small_config(TrackingMethod::kFullFusion);
  config.depth_scale_std = 0.005;
  const TrackerSetup setup(arm_model(), config, {"shoulder", "elbow"});
  EndEffectorFit fit(setup);
  const std::vector<double> mean(std::size_t(setup.n), 0.0);
  KinematicsState state(*setup.model);
  forward_kinematics(*setup.model, Eigen::VectorXd::Zero(setup.n), state);
  const Eigen::Isometry3d T_camera_tool =
      T_camera_link(*setup.model, state, setup.model->link_index("tool"));
  const Eigen::Vector3d X = T_camera_tool.translation();
  ASSERT_NEAR(X.norm(), std::hypot(1.0, 0.3), 1e-9);
  ImageInformation::RigidFit f;
  f.information = Eigen::Matrix<double, 6, 6>::Identity() * 1e8;
  f.pixels = 100;  // no motion: no scatter
  for (int k = 0; k <= 10; ++k) fit.update(0.1 * k, {f}, mean, mean, 0.0);
  const Eigen::Matrix3d R = T_camera_tool.linear();
  const Eigen::Matrix3d camera_axes = R * fit.estimates()[0].position_covariance_m2 * R.transpose();
  const Eigen::Matrix3d expected = 0.005 * 0.005 * X * X.transpose();
  EXPECT_LT((camera_axes - expected).norm(), 1e-12 * expected.norm()) << camera_axes;
}

}  // namespace
}  // namespace arttrack
