#include "arttrack/tracker/posterior_covariance.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

using Kind = PosteriorCovariance::Kind;

// One bias (OU) and one angle (random walk): prediction is the closed form
// of each process, and states stay uncorrelated without an image.
TEST(PosteriorCovariance, PredictsEachProcessInClosedForm) {
  const double k = 0.05, rate_b = 0.003, rate_a = 0.2;
  PosteriorCovariance cov({{0, Kind::kBias, k, rate_b}, {1, Kind::kAngle, 0, rate_a}});
  cov.reset(Eigen::Vector2d(0.01, 0.02), 1.0);
  cov.predict_to(3.0);
  const double phi = std::exp(-k * 2.0);
  EXPECT_NEAR(cov.covariance()(0, 0), phi * phi * 0.01 + rate_b * (1 - phi * phi) / (2 * k), 1e-15);
  EXPECT_NEAR(cov.covariance()(1, 1), 0.02 + rate_a * 2.0, 1e-15);
  EXPECT_EQ(cov.covariance()(0, 1), 0.0);
  EXPECT_NEAR(cov.variance_at(1, 4.0), cov.covariance()(1, 1) + rate_a, 1e-15);
  EXPECT_THROW(cov.predict_to(2.0), InputError);
}

// The update is the information-form product of Gaussians, (P^-1 + s D I D)^-1,
// and a bias is informed with the opposite sign of its angle.
TEST(PosteriorCovariance, UpdateIsTheInformationFormProduct) {
  PosteriorCovariance cov({{3, Kind::kBias, 0.05, 0.003}, {7, Kind::kAngle, 0, 1e-4}});
  Eigen::Matrix2d P0;
  P0 << 0.04, 0.01, 0.01, 0.09;
  cov.reset(P0.diagonal(), 0.0);
  cov.update(Eigen::Matrix2d::Zero(), 1.0);  // nothing learned: unchanged
  EXPECT_TRUE(cov.covariance().isApprox(Eigen::Matrix2d(P0.diagonal().asDiagonal()), 1e-15));

  Eigen::Matrix2d info;
  info << 200, 150, 150, 400;  // about the angles: positively correlated evidence
  const double s = 0.25;
  cov.update(info, s);
  const Eigen::Matrix2d D = Eigen::Vector2d(-1, 1).asDiagonal();
  const Eigen::Matrix2d expected =
      (Eigen::Matrix2d(P0.diagonal().asDiagonal()).inverse() + s * D * info * D).inverse();
  EXPECT_TRUE(cov.covariance().isApprox(expected, 1e-12));
  // The angle covariance flips the bias's sign back: angles positively correlated -> negative.
  EXPECT_LT(cov.angle_covariance()(0, 1), 0.0);

  // A restarted state forgets its correlations.
  cov.restart_state(0, 0.5);
  EXPECT_EQ(cov.covariance()(0, 1), 0.0);
  EXPECT_EQ(cov.covariance()(0, 0), 0.5);
}

TEST(PosteriorCovariance, RejectsBadInput) {
  EXPECT_THROW(PosteriorCovariance({{0, Kind::kBias, -1, 0.1}}), InputError);
  PosteriorCovariance cov({{0, Kind::kAngle, 0, 0.1}});
  EXPECT_THROW(cov.reset(Eigen::Vector2d(1, 1), 0), InputError);
  cov.reset(Eigen::VectorXd::Ones(1), 0);
  EXPECT_THROW(cov.update(Eigen::Matrix2d::Identity(), 1), InputError);
}

}  // namespace
}  // namespace arttrack
