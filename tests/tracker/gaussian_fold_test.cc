#include "arttrack/tracker/internal/gaussian_fold.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

namespace arttrack {
namespace {

// A random positive-definite 2-D Gaussian.
AngleBiasGaussian random_prior(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> mean(-1, 1), sd(0.01, 0.5), corr(-0.95, 0.95);
  const double sa = sd(rng), sb = sd(rng), rho = corr(rng);
  return {mean(rng), mean(rng), sa * sa, rho * sa * sb, sb * sb};
}

TEST(GaussianFold, KeepsTheConditionalOfBiasGivenAngle) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> new_mean(-1, 1), new_sd(0.001, 0.5);
  for (int trial = 0; trial < 1000; ++trial) {
    const AngleBiasGaussian prior = random_prior(rng);
    const double mu = new_mean(rng), s = new_sd(rng);
    const AngleBiasGaussian post = fold_angle_marginal(prior, mu, s * s);
    // The angle marginal is the new one.
    EXPECT_EQ(post.mean_a, mu);
    EXPECT_EQ(post.var_a, s * s);
    // p(b | a) is the prior's.
    const BiasGivenAngle before = bias_given_angle(prior);
    const BiasGivenAngle after = bias_given_angle(post);
    EXPECT_NEAR(after.slope, before.slope, 1e-12);
    EXPECT_NEAR(after.intercept, before.intercept, 1e-12);
    EXPECT_NEAR(after.residual_var, before.residual_var, 1e-12);
    // And the result is a valid covariance.
    EXPECT_GE(post.var_b, 0);
    EXPECT_GE(post.var_a * post.var_b - post.cov_ab * post.cov_ab, -1e-15);
  }
}

// If the new angle marginal is the exact posterior of a direct angle
// measurement y = a + N(0, R), folding must give the exact 2-D Kalman
// posterior with H = [1 0] (independent check through Eigen).
TEST(GaussianFold, EqualsExactPosteriorOfADirectAngleMeasurement) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> meas(-1, 1), noise_sd(0.005, 0.3);
  for (int trial = 0; trial < 200; ++trial) {
    const AngleBiasGaussian prior = random_prior(rng);
    const double y = meas(rng), r = std::pow(noise_sd(rng), 2);
    Eigen::Vector2d m(prior.mean_a, prior.mean_b);
    Eigen::Matrix2d P;
    P << prior.var_a, prior.cov_ab, prior.cov_ab, prior.var_b;
    const Eigen::RowVector2d H(1, 0);
    const double S = (H * P * H.transpose())(0) + r;
    const Eigen::Vector2d K = P * H.transpose() / S;
    const Eigen::Vector2d m_post = m + K * (y - H * m);
    const Eigen::Matrix2d P_post = (Eigen::Matrix2d::Identity() - K * H) * P;
    // 1-D posterior of the angle alone.
    const double var_a = 1 / (1 / prior.var_a + 1 / r);
    const double mean_a = var_a * (prior.mean_a / prior.var_a + y / r);
    const AngleBiasGaussian post = fold_angle_marginal(prior, mean_a, var_a);
    EXPECT_NEAR(post.mean_a, m_post(0), 1e-12);
    EXPECT_NEAR(post.mean_b, m_post(1), 1e-12);
    EXPECT_NEAR(post.var_a, P_post(0, 0), 1e-12);
    EXPECT_NEAR(post.cov_ab, P_post(0, 1), 1e-12);
    EXPECT_NEAR(post.var_b, P_post(1, 1), 1e-12);
  }
}

TEST(GaussianFold, UncorrelatedBiasIsUntouched) {
  const AngleBiasGaussian prior{0.3, 0.05, 0.01, 0.0, 0.002};
  const AngleBiasGaussian post = fold_angle_marginal(prior, -0.2, 1e-4);
  EXPECT_EQ(post.mean_b, 0.05);
  EXPECT_EQ(post.var_b, 0.002);
  EXPECT_EQ(post.cov_ab, 0.0);
}

TEST(GaussianFold, JointWithoutBiasStaysWithoutBias) {
  // Virtual joints and joints whose bias is not estimated: b = 0, no variance.
  const AngleBiasGaussian prior{0.3, 0.0, 0.01, 0.0, 0.0};
  const AngleBiasGaussian post = fold_angle_marginal(prior, 0.25, 0.004);
  EXPECT_EQ(post.mean_a, 0.25);
  EXPECT_EQ(post.var_a, 0.004);
  EXPECT_EQ(post.mean_b, 0.0);
  EXPECT_EQ(post.cov_ab, 0.0);
  EXPECT_EQ(post.var_b, 0.0);
}

TEST(GaussianFold, FullyCorrelatedPriorStaysFinite) {
  // Right after the first encoder reading a and b are nearly perfectly
  // anti-correlated (a + b is known); the fold must not produce NaN or a
  // negative variance.
  const double vb = 0.03, vq = 1e-12;
  const AngleBiasGaussian prior{0.5, 0.0, vb + vq, -vb, vb};
  const AngleBiasGaussian post = fold_angle_marginal(prior, 0.45, 1e-4);
  EXPECT_TRUE(std::isfinite(post.mean_b));
  EXPECT_GE(post.var_b, 0);
  // a + b stays at the reading: the bias absorbs the angle correction.
  EXPECT_NEAR(post.mean_a + post.mean_b, 0.5, 1e-9);
}

}  // namespace
}  // namespace arttrack
