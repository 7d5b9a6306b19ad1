#include "arttrack/tracker/internal/posterior_covariance.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "../count_allocations.h"
#include "../error_of.h"
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

// With consider parameters the reported covariance is that of the error of
// a mean fitted as if they were zero: brute force with an explicit
// measurement y = H_x x + H_c c + noise (R = Id / s), the nominal filter's
// gain K = P+ H_x^T R^-1, and the augmented error (e, c) propagated in
// Joseph form. Repeated images of one pose then leave the least-squares
// fit's error from c, (H_x^+ H_c)(H_x^+ H_c)^T, where the filter's own
// covariance goes to zero.
TEST(PosteriorCovariance, ConsiderParametersLeaveTheFitsErrorFloor) {
  const int m = 2, c = 3;
  const std::vector<PosteriorCovariance::State> states = {{3, Kind::kBias, 0.05, 0.003},
                                                          {7, Kind::kAngle, 0, 1e-4}};
  PosteriorCovariance cov(states, c);
  ASSERT_EQ(cov.num_consider(), c);
  Eigen::MatrixXd H(4, m + c);  // four measurements of the angles and the consider parameters
  H << 3, 1, 0.5, 0, 0.2,       //
      -1, 4, 0, 0.7, 0,         //
      2, 2, 0.1, 0.1, 0.6,      //
      0, 5, 0, 0.3, 0.3;
  const double s = 0.5;
  const Eigen::MatrixXd info = H.transpose() * H;  // about (angles, consider)
  const Eigen::MatrixXd I_xx = info.topLeftCorner(m, m), I_xc = info.topRightCorner(m, c);
  // The states are (bias, angle): the bias's column flips sign.
  Eigen::MatrixXd Hx = H.leftCols(m), Hc = H.rightCols(c);
  Hx.col(0) *= -1;
  cov.reset(Eigen::Vector2d(0.04, 0.09), 0.0);
  Eigen::MatrixXd P = Eigen::Vector2d(0.04, 0.09).asDiagonal();  // the nominal filter
  Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(m + c, m + c);   // (e, c)
  Q.topLeftCorner(m, m) = P;
  for (int image = 0; image < 3; ++image) {
    cov.update(I_xx, I_xc, s);
    P = (P.inverse() + s * Hx.transpose() * Hx).inverse();
    const Eigen::MatrixXd K = P * Hx.transpose() * s;  // R^-1 = s Id
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(m + c, m + c);
    A.topRows(m) -= K * H;  // e <- e - K (H_x e + H_c c) - K noise
    A.topLeftCorner(m, m) = Eigen::MatrixXd::Identity(m, m) - K * Hx;
    Q = A * Q * A.transpose();
    Q.topLeftCorner(m, m) += K * K.transpose() / s;
    EXPECT_TRUE(cov.nominal_covariance().isApprox(P, 1e-12));
    EXPECT_TRUE(cov.covariance().isApprox(Q.topLeftCorner(m, m), 1e-10)) << image << "\n"
                                                                         << cov.covariance() << "\n"
                                                                         << Q.topLeftCorner(m, m);
  }
  // Many images of the same pose: the reported covariance levels off at the
  // least-squares fit's error, the filter's own goes to zero.
  for (int image = 0; image < 5000; ++image) cov.update(I_xx, I_xc, s);
  const Eigen::MatrixXd regression = I_xx.inverse() * I_xc;  // the fit's shift per consider unit
  const Eigen::MatrixXd floor = regression * regression.transpose();
  EXPECT_TRUE(cov.angle_covariance().isApprox(floor, 0.01)) << cov.angle_covariance() << "\n"
                                                            << floor;
  Eigen::MatrixXd nominal;
  cov.nominal_angle_covariance(nominal);
  EXPECT_LT(nominal.trace(), 0.01 * floor.trace());
  // Without consider information the update is the plain one.
  PosteriorCovariance plain(states), with(states, c);
  plain.reset(Eigen::Vector2d(0.04, 0.09), 0.0);
  with.reset(Eigen::Vector2d(0.04, 0.09), 0.0);
  plain.update(I_xx, s);
  with.update(I_xx, s);
  EXPECT_EQ(plain.covariance(), with.nominal_covariance());
  EXPECT_TRUE(with.covariance().isApprox(plain.covariance(), 1e-12));
}

// A noise scale n (the image's pixels quieter than the weights assume)
// scales the pixel noise's term alone: the brute force above with the
// noise's covariance n R, the same gain K. The filter's own covariance
// (the weights) does not change.
TEST(PosteriorCovariance, NoiseScaleScalesThePixelNoisesTermAlone) {
  const int m = 2, c = 1;
  PosteriorCovariance cov({{3, Kind::kBias, 0.05, 0.003}, {7, Kind::kAngle, 0, 1e-4}}, c);
  PosteriorCovariance nominal({{3, Kind::kBias, 0.05, 0.003}, {7, Kind::kAngle, 0, 1e-4}}, c);
  Eigen::MatrixXd H(3, m + c);
  H << 3, 1, 0.5,  //
      -1, 4, 0.2,  //
      2, 2, 0.1;
  const double s = 0.5, n = 0.2;
  const Eigen::MatrixXd info = H.transpose() * H;
  const Eigen::MatrixXd I_xx = info.topLeftCorner(m, m), I_xc = info.topRightCorner(m, c);
  Eigen::MatrixXd Hx = H.leftCols(m);
  Hx.col(0) *= -1;
  cov.reset(Eigen::Vector2d(0.04, 0.09), 0.0);
  nominal.reset(Eigen::Vector2d(0.04, 0.09), 0.0);
  Eigen::MatrixXd P = Eigen::Vector2d(0.04, 0.09).asDiagonal();
  Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(m + c, m + c);
  Q.topLeftCorner(m, m) = P;
  for (int image = 0; image < 3; ++image) {
    cov.update(I_xx, I_xc, s, n);
    nominal.update(I_xx, I_xc, s);
    P = (P.inverse() + s * Hx.transpose() * Hx).inverse();
    const Eigen::MatrixXd K = P * Hx.transpose() * s;
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(m + c, m + c);
    A.topRows(m) -= K * H;
    A.topLeftCorner(m, m) = Eigen::MatrixXd::Identity(m, m) - K * Hx;
    Q = A * Q * A.transpose();
    Q.topLeftCorner(m, m) += n * K * K.transpose() / s;
    EXPECT_EQ(cov.nominal_covariance(), nominal.nominal_covariance());
    EXPECT_TRUE(cov.covariance().isApprox(Q.topLeftCorner(m, m), 1e-10)) << image;
  }
  EXPECT_LT(cov.covariance().trace(), nominal.covariance().trace());
}

// Process noise other than time's: added to the filter's and the reported
// variance of that state alone, the correlations kept.
TEST(PosteriorCovariance, AddedVarianceGrowsOneStateInBothCovariances) {
  PosteriorCovariance cov({{0, Kind::kAngle, 0, 0.1}, {1, Kind::kBias, 0.05, 0.003}}, 2);
  cov.reset(Eigen::Vector2d(1, 2), 0);
  Eigen::Matrix2d info;
  info << 3, 1, 1, 2;
  cov.update(info, Eigen::MatrixXd::Constant(2, 2, 0.5), 1);
  const Eigen::MatrixXd reported = cov.covariance(), nominal = cov.nominal_covariance();
  cov.add_variance(1, 0.25);
  Eigen::Matrix2d added = Eigen::Matrix2d::Zero();
  added(1, 1) = 0.25;
  EXPECT_LT((cov.covariance() - reported - added).norm(), 1e-15);
  EXPECT_LT((cov.nominal_covariance() - nominal - added).norm(), 1e-15);
  EXPECT_THROW(cov.add_variance(2, 0.1), InputError);
  EXPECT_THROW(cov.add_variance(0, -0.1), InputError);
  EXPECT_THROW(cov.add_variance(0, std::nan("")), InputError);
}

// What the estimate reports between images: angle_covariance_at() is a
// copy predicted to that time, to the bit, with and without consider
// parameters; the covariance itself is left where it was.
TEST(PosteriorCovariance, AngleCovarianceAtIsAPredictedCopy) {
  for (const int consider : {0, 2}) {
    PosteriorCovariance cov(
        {{0, Kind::kAngle, 0, 0.1}, {1, Kind::kBias, 0.05, 0.003}, {2, Kind::kBias, 0.2, 0.01}},
        consider);
    cov.reset(Eigen::Vector3d(1, 2, 0.5), 0.3);
    Eigen::Matrix3d info;
    info << 3, 1, -0.5, 1, 2, 0.2, -0.5, 0.2, 4;
    if (consider > 0)
      cov.update(info, Eigen::MatrixXd::Constant(3, consider, 0.5), 1);
    else
      cov.update(info, 1);
    const Eigen::MatrixXd before = cov.covariance();
    Eigen::MatrixXd at;
    for (const double t : {0.3, 0.31, 1.7}) {
      PosteriorCovariance copy = cov;
      copy.predict_to(t);
      cov.angle_covariance_at(t, at);
      EXPECT_EQ(at, copy.angle_covariance()) << "consider " << consider << ", t " << t;
    }
    EXPECT_NE(at, cov.angle_covariance());  // 1.4 s on: the biases' variances grew
    EXPECT_EQ(cov.covariance(), before);
    EXPECT_EQ(cov.time_s(), 0.3);
    EXPECT_THROW(cov.angle_covariance_at(0.2, at), InputError);
  }
}

// An image's update is on the image thread's path (per image, twice with
// the step-bound covariance, reported_covariance.h): once constructed, the
// covariance predicts, updates in each of its three forms and reports
// without a heap allocation, at the dual arm's size (about 20 states and
// 100 consider parameters: past Eigen's small fixed-size paths).
TEST(PosteriorCovariance, AnImageUpdateAllocatesNothing) {
  const int m = 20, c = 100;
  std::vector<PosteriorCovariance::State> states;
  for (int i = 0; i < m; ++i)
    states.push_back({i, i % 3 == 0 ? Kind::kAngle : Kind::kBias, i % 3 == 0 ? 0.0 : 0.05, 0.003});
  PosteriorCovariance cov(states, c);
  cov.reset(Eigen::VectorXd::Constant(m, 0.01), 0.0);
  // Fixed values, not drawn (any information and cross-information do).
  const Eigen::MatrixXd H =
      Eigen::MatrixXd::NullaryExpr(3 * m, m, [](Eigen::Index i, Eigen::Index j) {
        return std::sin(1.0 + double(i) + 0.7 * double(i * j));
      });
  const Eigen::MatrixXd info = H.transpose() * H;
  const Eigen::MatrixXd cross =
      Eigen::MatrixXd::NullaryExpr(m, c, [](Eigen::Index i, Eigen::Index j) {
        return std::cos(0.5 + double(j) + 0.3 * double(i * j));
      });
  const Eigen::MatrixXd widened_cross = 2 * cross;
  std::vector<char> widened(std::size_t(m), 0);
  widened[std::size_t(m - 1)] = 1;
  Eigen::MatrixXd out(m, m);
  const long before = g_allocations.load();
  for (int image = 1; image <= 10; ++image) {
    cov.predict_to(image / 30.0);
    cov.add_variance(0, 1e-4);
    cov.update(info, 0.5);
    cov.update(info, cross, 0.5);
    cov.update(info, cross, widened_cross, widened, 0.5);
    cov.angle_covariance(out);
    cov.angle_covariance_at(image / 30.0 + 0.01, out);
  }
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_TRUE(out.allFinite());
}

TEST(PosteriorCovariance, RejectsBadInput) {
  EXPECT_THROW(PosteriorCovariance({{0, Kind::kBias, -1, 0.1}}), InputError);
  PosteriorCovariance cov({{0, Kind::kAngle, 0, 0.1}});
  EXPECT_THROW(cov.reset(Eigen::Vector2d(1, 1), 0), InputError);
  cov.reset(Eigen::VectorXd::Ones(1), 0);
  EXPECT_THROW(cov.update(Eigen::Matrix2d::Identity(), 1), InputError);
  // With consider parameters, every part's size is checked and named.
  PosteriorCovariance with({{0, Kind::kAngle, 0, 0.1}, {1, Kind::kBias, 0.05, 0.003}}, 3);
  with.reset(Eigen::Vector2d(1, 1), 0);
  const Eigen::MatrixXd info = Eigen::Matrix2d::Identity(), cross = Eigen::MatrixXd::Zero(2, 3);
  const std::vector<char> flags = {1, 0};
  EXPECT_EQ(test_support::error_of([&] { with.update(Eigen::Matrix3d::Identity(), cross, 1); }),
            "posterior covariance: the information matrix is 3 x 3, not 2 x 2");
  EXPECT_EQ(test_support::error_of([&] { with.update(info, Eigen::MatrixXd::Zero(2, 2), 1); }),
            "posterior covariance: the consider cross-information is 2 x 2, not 2 x 3");
  EXPECT_EQ(test_support::error_of(
                [&] { with.update(info, cross, Eigen::MatrixXd::Zero(3, 3), flags, 1); }),
            "posterior covariance: the widened cross-information is 3 x 3, not 2 x 3");
  EXPECT_EQ(test_support::error_of([&] { with.update(info, cross, cross, {1}, 1); }),
            "posterior covariance: 1 widened flags, not one per state (2)");
  EXPECT_EQ(test_support::error_of([&] { with.update(info, cross, cross, flags, 1); }), "");
  EXPECT_EQ(test_support::error_of([&] { with.update(info, cross, 1, 1.5); }),
            "posterior covariance: noise scale 1.500000 is not in [0, 1]");
}

}  // namespace
}  // namespace arttrack
