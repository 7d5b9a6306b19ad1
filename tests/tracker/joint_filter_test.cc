#include "arttrack/tracker/internal/joint_filter.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "../expect_error.h"
#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

using test_support::expect_error_naming;

// Two encoder joints with different noises (one without bias) and two
// virtual joints.
JointFilterModel small_model() {
  JointFilterParams p0;
  p0.encoder_noise_rad = 2e-3;
  p0.angle_diffusion_rad_per_sqrt_s = 0.7;
  p0.bias_diffusion_rad_per_sqrt_s = 0.08;
  p0.bias_decay_per_s = 0.6;
  JointFilterParams p1;
  p1.estimate_bias = false;
  VirtualJointParams v0, v1;
  v0.diffusion_per_sqrt_s = 0.01;
  v1.diffusion_per_sqrt_s = 0.02;
  v1.initial_std = 0.1;
  return JointFilterModel({"shoulder", "elbow"}, {p0, p1}, {"cam_x", "cam_roll"}, {v0, v1});
}

// Continuous-time model of one joint: d(a, b) = A (a, b) dt + dW with
// A = diag(0, -k) and diffusion W = diag(sigma_a^2, sigma_b^2). Van Loan's
// method gives the exact discrete transition and process noise from one
// matrix exponential, independently of the closed forms in the filter.
void van_loan(double k, double rate_a, double rate_b, double dt, Eigen::Matrix2d& phi,
              Eigen::Matrix2d& q) {
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  A(1, 1) = -k;
  Eigen::Matrix2d W = Eigen::Matrix2d::Zero();
  W(0, 0) = rate_a;
  W(1, 1) = rate_b;
  Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
  M.topLeftCorner<2, 2>() = -A * dt;
  M.topRightCorner<2, 2>() = W * dt;
  M.bottomRightCorner<2, 2>() = A.transpose() * dt;
  const Eigen::Matrix4d E = M.exp();
  phi = E.bottomRightCorner<2, 2>().transpose();
  q = phi * E.topRightCorner<2, 2>();
}

Eigen::Matrix2d cov(const JointBelief& b, int j) {
  Eigen::Matrix2d P;
  P << b.var_a[j], b.cov_ab[j], b.cov_ab[j], b.var_b[j];
  return P;
}

TEST(JointFilter, PredictionIsTheExactDiscretisation) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> c(0.05, 0.99), sd(0.01, 1.0), dt(1e-4, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    JointFilterParams p;
    p.bias_decay_per_s = c(rng);
    p.angle_diffusion_rad_per_sqrt_s = sd(rng);
    p.bias_diffusion_rad_per_sqrt_s = sd(rng);
    const JointFilterModel model({"j"}, {p});
    const std::vector<double> q0 = {0.4};
    JointBelief b = initial_joint_belief(model, q0);
    b.mean_b[0] = 0.1;
    const Eigen::Vector2d m0(b.mean_a[0], b.mean_b[0]);
    const Eigen::Matrix2d P0 = cov(b, 0);
    const double step = dt(rng);
    predict_joints(model, step, b);
    Eigen::Matrix2d phi, q;
    van_loan(std::log(1 / p.bias_decay_per_s), std::pow(p.angle_diffusion_rad_per_sqrt_s, 2),
             std::pow(p.bias_diffusion_rad_per_sqrt_s, 2), step, phi, q);
    const Eigen::Vector2d m1 = phi * m0;
    const Eigen::Matrix2d P1 = phi * P0 * phi.transpose() + q;
    EXPECT_NEAR(b.mean_a[0], m1(0), 1e-12);
    EXPECT_NEAR(b.mean_b[0], m1(1), 1e-12);
    EXPECT_NEAR(b.var_a[0], P1(0, 0), 1e-10 * P1(0, 0));
    EXPECT_NEAR(b.cov_ab[0], P1(0, 1), 1e-10 * std::abs(P1(0, 1)) + 1e-15);
    EXPECT_NEAR(b.var_b[0], P1(1, 1), 1e-10 * P1(1, 1));
  }
}

// An encoder's noise may be raised to what its readings show (the
// tracker's encoder_noise.from_readings); nothing else, and only to a
// finite positive variance of an encoder joint (an error naming it).
TEST(JointFilter, AnEncodersNoiseCanBeRaisedAndNothingElse) {
  JointFilterModel model = small_model();
  model.set_encoder_var(0, 1e-5);
  EXPECT_EQ(model.encoder_var_rad2()[0], 1e-5);
  test_support::expect_error_naming([&] { model.set_encoder_var(0, -1.0); }, "shoulder");
  EXPECT_THROW(model.set_encoder_var(2, 1e-5), InputError);  // a virtual joint
  EXPECT_THROW(model.set_encoder_var(-1, 1e-5), InputError);
  EXPECT_EQ(model.encoder_var_rad2()[0], 1e-5);
}

TEST(JointFilter, PredictionDoesNotDependOnTheStepSize) {
  // Exact discretisation: one step of 0.5 s, 500 steps of 1 ms and irregular
  // steps summing to 0.5 s give the same belief (the per-step formula of the
  // paper's Eq. (5) would not).
  const JointFilterModel model = small_model();
  const std::vector<double> q0 = {0.3, -0.2};
  JointBelief one = initial_joint_belief(model, q0);
  one.mean_b[0] = 0.12;
  JointBelief many = one, irregular = one;
  predict_joints(model, 0.5, one);
  for (int i = 0; i < 500; ++i) predict_joints(model, 1e-3, many);
  const double steps[] = {0.1, 0.0003, 0.25, 0.0497, 0.05, 0.0, 0.05};
  for (double s : steps) predict_joints(model, s, irregular);
  for (const JointBelief* b : {&many, &irregular}) {
    for (int j = 0; j < model.num_joints(); ++j) {
      EXPECT_NEAR(b->mean_a[j], one.mean_a[j], 1e-12);
      EXPECT_NEAR(b->mean_b[j], one.mean_b[j], 1e-12);
      EXPECT_NEAR(b->var_a[j], one.var_a[j], 1e-12 * one.var_a[j]);
      EXPECT_NEAR(b->cov_ab[j], one.cov_ab[j], 1e-12 * std::abs(one.cov_ab[j]) + 1e-18);
      EXPECT_NEAR(b->var_b[j], one.var_b[j], 1e-12 * one.var_b[j] + 1e-18);
    }
  }
}

TEST(JointFilter, StationaryBiasVarianceHoldsAtEveryRate) {
  JointFilterParams p;
  p.bias_decay_per_s = 0.8;
  p.bias_diffusion_rad_per_sqrt_s = 0.1;
  const double stationary = 0.01 / (2 * std::log(1 / 0.8));
  EXPECT_NEAR(p.stationary_bias_std_rad(), std::sqrt(stationary), 1e-15);
  const JointFilterModel model({"j"}, {p});
  for (double dt : {1e-3, 3e-3, 0.033, 1.0}) {
    const std::vector<double> q0 = {0.0};
    JointBelief b = initial_joint_belief(model, q0);
    EXPECT_NEAR(b.var_b[0], stationary, 1e-15);
    for (int i = 0; i < 100; ++i) predict_joints(model, dt, b);
    EXPECT_NEAR(b.var_b[0], stationary, 1e-12 * stationary) << "dt " << dt;
  }
}

// The measurement update against the information form of Bayes' rule for
// the linear-Gaussian model, through Eigen, over a random run with variable
// time steps.
TEST(JointFilter, FilteringMatchesInformationFormReference) {
  const JointFilterModel model = small_model();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> dt(2e-4, 5e-3), q(-1, 1);
  std::vector<double> reading = {q(rng), q(rng)};
  JointBelief b = initial_joint_belief(model, reading);
  std::vector<Eigen::Vector2d> m(4);
  std::vector<Eigen::Matrix2d> P(4);
  for (int j = 0; j < 4; ++j) {
    m[j] = Eigen::Vector2d(b.mean_a[j], b.mean_b[j]);
    P[j] = cov(b, j);
  }
  for (int step = 0; step < 300; ++step) {
    const double h = dt(rng);
    reading = {q(rng), q(rng)};
    filter_joints(model, h, reading, b);
    for (int j = 0; j < 4; ++j) {
      Eigen::Matrix2d phi, Q;
      van_loan(model.bias_decay_rate_per_s()[j], model.angle_rate_var()[j],
               model.bias_rate_var()[j], h, phi, Q);
      m[j] = phi * m[j];
      P[j] = phi * P[j] * phi.transpose() + Q;
      if (j < model.num_encoder_joints()) {
        const double r = model.encoder_var_rad2()[j];
        if (model.bias_rate_var()[j] > 0) {
          const Eigen::Matrix2d info = P[j].inverse() + Eigen::Matrix2d::Ones() / r;
          const Eigen::Matrix2d P_post = info.inverse();
          m[j] = P_post * (P[j].inverse() * m[j] + Eigen::Vector2d::Ones() * reading[j] / r);
          P[j] = P_post;
        } else {  // no bias: scalar filter on the angle
          const double var = 1 / (1 / P[j](0, 0) + 1 / r);
          m[j](0) = var * (m[j](0) / P[j](0, 0) + reading[j] / r);
          P[j](0, 0) = var;
        }
      }
      EXPECT_NEAR(b.mean_a[j], m[j](0), 1e-9) << "joint " << j << " step " << step;
      EXPECT_NEAR(b.mean_b[j], m[j](1), 1e-9);
      EXPECT_NEAR(b.var_a[j], P[j](0, 0), 1e-9 * P[j](0, 0));
      EXPECT_NEAR(b.cov_ab[j], P[j](0, 1), 1e-9 * std::sqrt(P[j](0, 0) * P[j](1, 1)) + 1e-18);
      EXPECT_NEAR(b.var_b[j], P[j](1, 1), 1e-9 * P[j](1, 1) + 1e-18);
    }
  }
}

TEST(JointFilter, FilterStepEqualsPredictThenUpdate) {
  const JointFilterModel model = small_model();
  const std::vector<double> q0 = {0.1, 0.2}, q1 = {0.12, 0.19};
  JointBelief fused = initial_joint_belief(model, q0), split = fused;
  filter_joints(model, 2e-3, q1, fused);
  predict_joints(model, 2e-3, split);
  update_encoders(model, q1, split);
  EXPECT_EQ(fused.mean_a, split.mean_a);
  EXPECT_EQ(fused.mean_b, split.mean_b);
  EXPECT_EQ(fused.var_a, split.var_a);
  EXPECT_EQ(fused.cov_ab, split.cov_ab);
  EXPECT_EQ(fused.var_b, split.var_b);
}

TEST(JointFilter, JointWithoutBiasKeepsZeroBias) {
  const JointFilterModel model = small_model();  // "elbow" has no bias
  std::vector<double> q = {0.0, 0.5};
  JointBelief b = initial_joint_belief(model, q);
  for (int i = 0; i < 1000; ++i) {
    q[1] = 0.5 + 0.1 * std::sin(i * 0.01);
    filter_joints(model, 1e-3, q, b);
  }
  EXPECT_EQ(b.mean_b[1], 0.0);
  EXPECT_EQ(b.var_b[1], 0.0);
  EXPECT_EQ(b.cov_ab[1], 0.0);
  EXPECT_NEAR(b.mean_a[1], q[1], 0.005);
}

TEST(JointFilter, VirtualJointsAreRandomWalksWithoutEncoder) {
  const JointFilterModel model = small_model();
  EXPECT_EQ(model.num_virtual_joints(), 2);
  EXPECT_EQ(model.index_of("cam_roll"), 3);
  EXPECT_TRUE(model.is_virtual(3));
  EXPECT_EQ(model.index_of("nope"), -1);
  const std::vector<double> q = {0.1, 0.2};
  JointBelief b = initial_joint_belief(model, q);
  EXPECT_EQ(b.mean_a[2], 0.0);
  EXPECT_NEAR(b.var_a[3], 0.01, 1e-15);
  b.mean_a[2] = 0.02;
  for (int i = 0; i < 100; ++i) filter_joints(model, 0.01, q, b);
  EXPECT_EQ(b.mean_a[2], 0.02);  // no measurement moves it
  EXPECT_NEAR(b.var_a[2], 0.03 * 0.03 + 1e-4 * 1.0, 1e-15);
  EXPECT_NEAR(b.var_a[3], 0.01 + 4e-4 * 1.0, 1e-15);
  EXPECT_EQ(b.var_b[2], 0.0);
}

TEST(JointFilter, CovarianceStaysPositiveWithVeryPreciseEncoders) {
  JointFilterParams p;
  p.encoder_noise_rad = 1e-9;
  p.angle_diffusion_rad_per_sqrt_s = 5.0;
  const JointFilterModel model({"j"}, {p});
  std::vector<double> q = {0.0};
  JointBelief b = initial_joint_belief(model, q);
  for (int i = 0; i < 100000; ++i) {
    q[0] = std::sin(i * 1e-3);
    filter_joints(model, 1e-3, q, b);
    ASSERT_GT(b.var_a[0], 0);
    ASSERT_GT(b.var_b[0], 0);
    // Positive semi-definite to the rounding of the determinant itself.
    ASSERT_GE(b.var_a[0] * b.var_b[0] - b.cov_ab[0] * b.cov_ab[0], -1e-12 * b.var_a[0] * b.var_b[0])
        << i;
  }
}

// Encoders alone cannot tell angle from bias; images can. Feed a constant
// bias of 0.15 rad and, every 33 ms, an angle posterior as the particle
// filter would give it (the true angle with 5 mrad uncertainty), folded in:
// the bias estimate converges to the true bias.
TEST(JointFilter, ImagesFoldedInTeachTheBias) {
  JointFilterParams p;  // defaults: stationary bias std 10 degrees
  const JointFilterModel model({"j"}, {p});
  const double true_bias = 0.15, dt = 1e-3;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> enc_noise(0, p.encoder_noise_rad), img_noise(0, 0.005);
  auto angle = [](double t) { return 0.5 * std::sin(0.7 * t); };
  std::vector<double> q = {angle(0) + true_bias};
  JointBelief b = initial_joint_belief(model, q);
  EXPECT_NEAR(b.mean_b[0], 0.0, 1e-15);  // no idea of the bias yet
  for (int i = 1; i <= 20000; ++i) {
    const double t = i * dt;
    q[0] = angle(t) + true_bias + enc_noise(rng);
    filter_joints(model, dt, q, b);
    if (i % 33 == 0) {
      const double var = 0.005 * 0.005;
      const std::vector<double> mean = {angle(t) + img_noise(rng)}, v = {var};
      fold_angle_posteriors(mean, v, b);
    }
  }
  EXPECT_NEAR(b.mean_b[0], true_bias, 0.01);
  EXPECT_NEAR(b.mean_a[0], angle(20.0), 0.01);
  EXPECT_LT(std::sqrt(b.var_b[0]), 0.01);
}

TEST(JointFilter, RejectsBadInput) {
  JointFilterParams bad_c;
  bad_c.bias_decay_per_s = 1.0;
  EXPECT_THROW(JointFilterModel({"j"}, {bad_c}), InputError);
  JointFilterParams bad_q;
  bad_q.encoder_noise_rad = -1;
  expect_error_naming(
      [&] {
        JointFilterModel({"ok", "elbow"}, {JointFilterParams{}, bad_q});
      },
      "elbow");
  EXPECT_THROW(JointFilterModel({"j", "j"}, {JointFilterParams{}, JointFilterParams{}}),
               InputError);
  EXPECT_THROW(JointFilterModel({"j"}, {}), InputError);

  const JointFilterModel model = small_model();
  const std::vector<double> q = {0.1, 0.2};
  JointBelief b = initial_joint_belief(model, q);
  const JointBelief before = b;
  EXPECT_THROW(predict_joints(model, -1e-3, b), InputError);
  EXPECT_THROW(predict_joints(model, std::nan(""), b), InputError);
  const std::vector<double> nan_reading = {0.1, std::nan("")};
  expect_error_naming([&] { filter_joints(model, 1e-3, nan_reading, b); }, "elbow");
  const std::vector<double> too_few = {0.1};
  EXPECT_THROW(update_encoders(model, too_few, b), InputError);
  EXPECT_EQ(b.mean_a, before.mean_a);  // nothing changed
  EXPECT_EQ(b.var_a, before.var_a);
}

}  // namespace
}  // namespace arttrack
