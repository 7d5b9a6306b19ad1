// EstimateReport (tracker/internal): what Tracker::estimate() reports from
// a belief, the readings and the reported covariance.
#include "arttrack/tracker/internal/estimate_report.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <span>
#include <vector>

#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)

// Encoders only: the readings, with the encoder noise and the bias prior's
// stationary spread; no bias, no camera offset.
TEST(EstimateReport, EncodersOnlyReportsTheReadingsWithTheBiasPriorsSpread) {
  const TrackerSetup setup(arm_model(), small_config(TrackingMethod::kEncodersOnly),
                           {"shoulder", "elbow"});
  EstimateReport report(setup);
  JointBelief belief = initial_joint_belief(*setup.filter_model, std::vector<double>{0.1, 0.2});
  belief.mean_a[0] = 7;  // not what encoders only reports
  const std::vector<double> readings{0.3, -0.2};
  TrackerEstimate e;
  report.fill(belief, readings, 2.5, PosteriorCovariance(), {}, {}, e);
  EXPECT_EQ(e.time_s, 2.5);
  EXPECT_EQ(e.joint_names, (std::vector<std::string>{"shoulder", "elbow"}));
  EXPECT_EQ(e.angle_rad[0], 0.3);
  EXPECT_EQ(e.angle_rad[1], -0.2);
  const JointFilterParams& p = setup.config.joint_defaults;
  for (int j = 0; j < 2; ++j) {
    EXPECT_DOUBLE_EQ(e.angle_std_rad[j],
                     std::hypot(p.encoder_noise_rad, p.stationary_bias_std_rad()));
    EXPECT_EQ(e.bias_rad[j], 0.0);
    EXPECT_EQ(e.bias_std_rad[j], 0.0);
  }
  for (int k = 0; k < 6; ++k) EXPECT_EQ(e.camera_offset[k], 0.0);
  ASSERT_EQ(e.T_camera_ee.size(), 1u);
}

// The straight arm (both joints about x): the tool moves 0.55 m from the
// shoulder's axis and 0.25 m from the elbow's, so its position covariance's
// trace is 0.55^2 var_shoulder + 0.25^2 var_elbow and its rotation's
// var_shoulder + var_elbow (the camera's variance 0).
TEST(EstimateReport, EndEffectorCovarianceFollowsTheKinematics) {
  const TrackerSetup setup(arm_model(), small_config(TrackingMethod::kFullFusion),
                           {"shoulder", "elbow"});
  EstimateReport report(setup);
  JointBelief belief = initial_joint_belief(*setup.filter_model, std::vector<double>{0.0, 0.0});
  const int shoulder = setup.model->joint_index("shoulder");
  const int elbow = setup.model->joint_index("elbow");
  belief.var_a[std::size_t(shoulder)] = 0.01 * 0.01;
  belief.var_a[std::size_t(elbow)] = 0.02 * 0.02;
  for (int j = setup.n_phys; j < setup.n; ++j) belief.var_a[std::size_t(j)] = 0;
  TrackerEstimate e;
  report.fill(belief, std::vector<double>{0.0, 0.0}, 0.0, PosteriorCovariance(), {}, {}, e);
  EXPECT_DOUBLE_EQ(e.angle_std_rad[std::size_t(shoulder)], 0.01);
  ASSERT_EQ(e.T_camera_ee_covariance.size(), 1u);
  const Eigen::Matrix<double, 6, 6>& cov = e.T_camera_ee_covariance[0];
  const double var_s = 0.01 * 0.01, var_e = 0.02 * 0.02;
  EXPECT_NEAR((cov.topLeftCorner<3, 3>().trace()), 0.55 * 0.55 * var_s + 0.25 * 0.25 * var_e, 1e-9);
  EXPECT_NEAR((cov.bottomRightCorner<3, 3>().trace()), var_s + var_e, 1e-9);
}

// A mean's lag (mean_lag.h) adds to its state's reported variance: the
// bias's and the angle's (a = q - b), and through them the hand's.
TEST(EstimateReport, AMeansLagWidensItsStateAndTheHand) {
  const TrackerSetup setup(arm_model(), small_config(TrackingMethod::kFullFusion),
                           {"shoulder", "elbow"});
  EstimateReport report(setup);
  const JointBelief belief =
      initial_joint_belief(*setup.filter_model, std::vector<double>{0.0, 0.0});
  const int shoulder = setup.model->joint_index("shoulder");
  const int elbow = setup.model->joint_index("elbow");
  PosteriorCovariance cov(
      {{shoulder, PosteriorCovariance::Kind::kBias}, {elbow, PosteriorCovariance::Kind::kBias}});
  cov.reset(Eigen::Vector2d(1e-4, 4e-4), 0.0);
  const std::vector<double> readings{0.0, 0.0}, lag{9e-4, 0.0};
  TrackerEstimate plain, lagging;
  report.fill(belief, readings, 0.0, cov, {}, {}, plain);
  report.fill(belief, readings, 0.0, cov, lag, {}, lagging);
  const std::size_t s = std::size_t(shoulder), el = std::size_t(elbow);
  EXPECT_DOUBLE_EQ(plain.bias_std_rad[s], 0.01);
  EXPECT_DOUBLE_EQ(lagging.bias_std_rad[s], std::sqrt(1e-3));
  EXPECT_NEAR(lagging.angle_std_rad[s] * lagging.angle_std_rad[s] -
                  plain.angle_std_rad[s] * plain.angle_std_rad[s],
              9e-4, 1e-15);
  EXPECT_EQ(lagging.bias_std_rad[el], plain.bias_std_rad[el]);
  EXPECT_EQ(lagging.angle_std_rad[el], plain.angle_std_rad[el]);
  // The tool is 0.55 m from the shoulder's axis.
  EXPECT_NEAR((lagging.T_camera_ee_covariance[0].topLeftCorner<3, 3>().trace() -
               plain.T_camera_ee_covariance[0].topLeftCorner<3, 3>().trace()),
              0.55 * 0.55 * 9e-4, 1e-12);
  EXPECT_THROW(report.fill(belief, readings, 0.0, cov, std::vector<double>{1e-4}, {}, lagging),
               std::invalid_argument);
}

// Full fusion's report on the planar arm at (0.3, -0.2), before any image,
// with the end-effector fits `fits`.
TrackerEstimate full_fusion_estimate(std::span<const EndEffectorFitEstimate> fits) {
  const TrackerSetup setup(arm_model(), small_config(TrackingMethod::kFullFusion),
                           {"shoulder", "elbow"});
  EstimateReport report(setup);
  const JointBelief belief =
      initial_joint_belief(*setup.filter_model, std::vector<double>{0.3, -0.2});
  TrackerEstimate e;
  report.fill(belief, std::vector<double>{0.3, -0.2}, 0.0, PosteriorCovariance(), {}, fits, e);
  return e;
}

// An end-effector fit's correction (end_effector_fit.h) moves the reported
// pose by that rigid motion in the end effector's own axes, and is reported
// as given; with no weight (no image showed it) the covariance stays the
// joints'.
TEST(EstimateReport, EndEffectorCorrectionMovesThePoseInItsOwnAxes) {
  const TrackerEstimate plain = full_fusion_estimate({});
  EndEffectorCorrection c;
  c << 0.004, -0.002, 0.003, 0.0, 0.02, 0.0;  // m, then rad about the tool's y
  std::vector<EndEffectorFitEstimate> fits(1);
  fits[0].correction = c;
  const TrackerEstimate corrected = full_fusion_estimate(fits);
  const Eigen::Isometry3d expected = plain.T_camera_ee[0] *
                                     Eigen::Translation3d(0.004, -0.002, 0.003) *
                                     Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY());
  EXPECT_TRUE(corrected.T_camera_ee[0].isApprox(expected, 1e-12));
  EXPECT_EQ(corrected.ee_image_correction[0], c);
  EXPECT_EQ(plain.ee_image_correction[0], EndEffectorCorrection::Zero());
  EXPECT_EQ(corrected.T_camera_ee_covariance[0], plain.T_camera_ee_covariance[0]);
}

// With weight a the reported position is (1 - a) the kinematics' and a the
// fits': its covariance (1 - a)^2 C + a^2 R F R^T (F in the tool's axes,
// R the kinematics' rotation), the cross terms (1 - a) C's, the rotation's
// C's.
TEST(EstimateReport, EndEffectorFitWeighsThePositionCovariance) {
  const TrackerEstimate plain = full_fusion_estimate({});
  std::vector<EndEffectorFitEstimate> fits(1);
  fits[0].weight = 0.75;
  fits[0].position_covariance_m2 = Eigen::Vector3d(4e-6, 1e-6, 9e-6).asDiagonal();
  fits[0].position_covariance_m2(0, 1) = fits[0].position_covariance_m2(1, 0) = 1e-6;
  const TrackerEstimate fitted = full_fusion_estimate(fits);
  const Eigen::Matrix<double, 6, 6>& C = plain.T_camera_ee_covariance[0];
  const Eigen::Matrix<double, 6, 6>& got = fitted.T_camera_ee_covariance[0];
  const Eigen::Matrix3d R = plain.T_camera_ee[0].linear();
  const Eigen::Matrix3d position = 0.25 * 0.25 * C.topLeftCorner<3, 3>() +
                                   0.75 * 0.75 * R * fits[0].position_covariance_m2 * R.transpose();
  EXPECT_LT((got.topLeftCorner<3, 3>() - position).norm(), 1e-18);
  EXPECT_LT((got.topRightCorner<3, 3>() - 0.25 * C.topRightCorner<3, 3>()).norm(), 1e-18);
  EXPECT_LT((got.bottomLeftCorner<3, 3>() - 0.25 * C.bottomLeftCorner<3, 3>()).norm(), 1e-18);
  EXPECT_EQ((got.bottomRightCorner<3, 3>()), (C.bottomRightCorner<3, 3>()));
  EXPECT_GT((C.topLeftCorner<3, 3>().trace()), 0);  // the arm's joints are uncertain
}

}  // namespace
}  // namespace arttrack
