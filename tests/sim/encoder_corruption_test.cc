#include "arttrack/sim/encoder_corruption.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../expect_error.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

using test_support::expect_error_naming;

const std::vector<std::string> kJoints = {"j1", "j2", "j3"};

EncoderCorruptionParams one_group(const EncoderGroupCorruption& g) {
  EncoderCorruptionParams p;
  p.groups.push_back(g);
  return p;
}

TEST(EncoderCorruption, NoCorruptionReadsTheTruth) {
  EncoderCorruption enc(kJoints, {}, 1);
  const std::vector<double> angles = {0.1, -0.2, 1.3};
  std::vector<double> out(3);
  enc.corrupt(0.0, 0.0, angles, {}, out);
  EXPECT_EQ(out, angles);
  EXPECT_EQ(enc.bias_rad()[1], 0.0);
}

TEST(EncoderCorruption, ConstantOffsetOnAGroup) {
  EncoderGroupCorruption g;
  g.joints = {"j1", "j3"};
  g.offset_rad = 0.15;
  EncoderCorruption enc(kJoints, one_group(g), 1);
  const std::vector<double> angles = {0.1, -0.2, 1.3};
  std::vector<double> out(3);
  for (double t = 0.0; t < 1.0; t += 0.25) {
    enc.corrupt(t, 0.25, angles, {}, out);
    EXPECT_DOUBLE_EQ(out[0], 0.25);
    EXPECT_DOUBLE_EQ(out[1], -0.2);
    EXPECT_DOUBLE_EQ(out[2], 1.45);
    EXPECT_EQ(enc.bias_rad()[0], 0.15);
    EXPECT_EQ(enc.bias_rad()[1], 0.0);
  }
}

TEST(EncoderCorruption, AlternatingStepClosedForm) {
  // Period 10 s, ramps of 2 s: +A on [0, 3), ramp to -A on [3, 5), -A on
  // [5, 8), ramp to +A on [8, 10).
  const double A = 5.0 * std::numbers::pi / 180.0;
  auto step = [&](double t) { return alternating_step_rad(t, A, 10.0, 2.0); };
  EXPECT_EQ(step(0.0), A);
  EXPECT_EQ(step(2.9), A);
  EXPECT_NEAR(step(3.5), A * std::cos(std::numbers::pi / 4), 1e-15);
  EXPECT_NEAR(step(4.0), 0.0, 1e-15);
  EXPECT_NEAR(step(4.5), -A * std::cos(std::numbers::pi / 4), 1e-15);
  EXPECT_NEAR(step(5.0), -A, 1e-15);
  EXPECT_EQ(step(7.9), -A);
  EXPECT_NEAR(step(9.0), 0.0, 1e-15);
  EXPECT_NEAR(step(10.0), A, 1e-15);
  EXPECT_NEAR(step(13.5), A * std::cos(std::numbers::pi / 4), 1e-15);
  EXPECT_NEAR(step(23.5), A * std::cos(std::numbers::pi / 4), 1e-15);
  // Continuous: slope at most A pi / r rad/s.
  for (double t = 0.0; t < 40.0; t += 1e-3)
    EXPECT_LE(std::abs(step(t + 1e-3) - step(t)), A * std::numbers::pi / 2.0 * 1e-3 * 1.0001) << t;
  // Abrupt steps with no ramp.
  EXPECT_EQ(alternating_step_rad(4.99, A, 10.0, 0.0), A);
  EXPECT_EQ(alternating_step_rad(5.01, A, 10.0, 0.0), -A);
}

TEST(EncoderCorruption, StepThroughCorruptIsTheBias) {
  EncoderGroupCorruption g;
  g.step_amplitude_rad = 0.1;
  g.step_period_s = 6.0;
  g.step_ramp_time_s = 1.0;
  g.offset_rad = 0.02;
  EncoderCorruption enc(kJoints, one_group(g), 1);
  const std::vector<double> angles = {0.0, 0.5, 1.0};
  std::vector<double> out(3);
  for (double t = 0.0; t < 20.0; t += 0.01) {
    enc.corrupt(t, 0.01, angles, {}, out);
    const double b = 0.02 + alternating_step_rad(t, 0.1, 6.0, 1.0);
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(enc.bias_rad()[j], b, 1e-15);
      EXPECT_NEAR(out[j], angles[j] + b, 1e-15);
    }
  }
}

TEST(EncoderCorruption, CableStretchLagStepResponseAtAnyDt) {
  EncoderGroupCorruption g;
  g.joints = {"j2"};
  g.compliance_rad_per_Nm = 0.004;
  g.stretch_time_constant_s = 0.08;
  const double torque = 12.0, final_bias = 0.004 * 12.0;
  std::mt19937_64 steps(5);
  std::uniform_real_distribution<double> random_dt(1e-4, 0.03);
  for (int variant = 0; variant < 4; ++variant) {
    EncoderCorruption enc(kJoints, one_group(g), 1);
    const std::vector<double> angles = {0.0, 0.3, 0.0}, torques = {5.0, torque, -3.0};
    std::vector<double> out(3);
    enc.corrupt(0.0, 0.0, angles, torques, out);  // torque applied from t = 0
    EXPECT_EQ(enc.bias_rad()[1], 0.0);
    double t = 0.0;
    while (t < 0.5) {
      const double dt = variant == 0   ? 1e-3
                        : variant == 1 ? 0.0037
                        : variant == 2 ? 0.05
                                       : random_dt(steps);
      t += dt;
      enc.corrupt(t, dt, angles, torques, out);
      const double expected = final_bias * (1.0 - std::exp(-t / 0.08));
      EXPECT_NEAR(enc.bias_rad()[1], expected, 1e-14) << variant << " " << t;
      EXPECT_NEAR(out[1], 0.3 + expected, 1e-14);
      EXPECT_EQ(enc.bias_rad()[0], 0.0);  // other joints: no stretch
    }
  }
}

TEST(EncoderCorruption, CableStretchWithoutLagFollowsTheTorque) {
  EncoderGroupCorruption g;
  g.compliance_rad_per_Nm = 0.01;
  g.stretch_time_constant_s = 0.0;
  EncoderCorruption enc(kJoints, one_group(g), 1);
  std::vector<double> out(3);
  enc.corrupt(0.1, 0.1, std::vector<double>{0, 0, 0}, std::vector<double>{1.0, -2.0, 0.5}, out);
  EXPECT_DOUBLE_EQ(enc.bias_rad()[0], 0.01);
  EXPECT_DOUBLE_EQ(enc.bias_rad()[1], -0.02);
  EXPECT_DOUBLE_EQ(enc.bias_rad()[2], 0.005);
}

TEST(EncoderCorruption, QuantisationRoundsToNearestMultiple) {
  EncoderGroupCorruption g;
  g.resolution_rad = 0.01;
  EncoderCorruption enc(kJoints, one_group(g), 1);
  std::vector<double> out(3);
  enc.corrupt(0.0, 0.0, std::vector<double>{0.1234, -0.1266, 0.0049}, {}, out);
  EXPECT_NEAR(out[0], 0.12, 1e-15);
  EXPECT_NEAR(out[1], -0.13, 1e-15);
  EXPECT_EQ(out[2], 0.0);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (int i = 0; i < 10000; ++i) {
    const std::vector<double> a = {angle(rng), angle(rng), angle(rng)};
    enc.corrupt(0.0, 0.0, a, {}, out);
    for (int j = 0; j < 3; ++j) {
      EXPECT_LE(std::abs(out[j] - a[j]), 0.005 + 1e-12);
      EXPECT_NEAR(out[j] / 0.01, std::round(out[j] / 0.01), 1e-9);
    }
  }
}

TEST(EncoderCorruption, NoiseStatisticsAndVariancesAdd) {
  EncoderGroupCorruption all, extra;
  all.noise_sigma_rad = 0.003;
  extra.joints = {"j3"};
  extra.noise_sigma_rad = 0.004;  // j3: sqrt(3^2 + 4^2) = 5 mrad
  EncoderCorruptionParams p;
  p.groups = {all, extra};
  EncoderCorruption enc(kJoints, p, 2024);
  const std::vector<double> angles = {0.2, 0.4, 0.6};
  std::vector<double> out(3), sum(3, 0.0), sum2(3, 0.0);
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    enc.corrupt(i * 1e-3, 1e-3, angles, {}, out);
    EXPECT_EQ(enc.bias_rad()[0], 0.0);  // noise is not bias
    for (int j = 0; j < 3; ++j) {
      sum[j] += out[j] - angles[j];
      sum2[j] += (out[j] - angles[j]) * (out[j] - angles[j]);
    }
  }
  const double sigma[3] = {0.003, 0.003, 0.005};
  for (int j = 0; j < 3; ++j) {
    const double mean = sum[j] / n, sd = std::sqrt(sum2[j] / n - mean * mean);
    // 5 standard errors: mean's sigma / sqrt(n), the std's sigma / sqrt(2 n).
    EXPECT_NEAR(mean, 0.0, 5 * sigma[j] / std::sqrt(n)) << j;
    EXPECT_NEAR(sd, sigma[j], 5 * sigma[j] / std::sqrt(2.0 * n)) << j;
  }
}

TEST(EncoderCorruption, SameSeedSameReadings) {
  EncoderGroupCorruption g;
  g.noise_sigma_rad = 0.01;
  g.resolution_rad = 0.001;
  auto run = [&](std::uint64_t seed) {
    EncoderCorruption enc(kJoints, one_group(g), seed);
    std::vector<double> all, out(3);
    for (int i = 0; i < 100; ++i) {
      enc.corrupt(i * 1e-3, 1e-3, std::vector<double>{0.1, 0.2, 0.3}, {}, out);
      all.insert(all.end(), out.begin(), out.end());
    }
    return all;
  };
  EXPECT_EQ(run(7), run(7));
  EXPECT_NE(run(7), run(8));
}

TEST(EncoderCorruption, BadInputIsNamed) {
  EncoderGroupCorruption g;
  g.noise_sigma_rad = -1.0;
  expect_error_naming([&] { EncoderCorruption(kJoints, one_group(g), 1); }, "noise_sigma_rad");
  g = {};
  g.step_amplitude_rad = 0.1;
  g.step_period_s = 2.0;
  g.step_ramp_time_s = 1.5;
  expect_error_naming([&] { EncoderCorruption(kJoints, one_group(g), 1); }, "step_ramp_time_s");
  g = {};
  g.joints = {"elbow"};
  expect_error_naming([&] { EncoderCorruption(kJoints, one_group(g), 1); }, "elbow");
  EncoderGroupCorruption q1, q2;
  q1.resolution_rad = 0.01;
  q2.joints = {"j2"};
  q2.resolution_rad = 0.02;
  EncoderCorruptionParams two;
  two.groups = {q1, q2};
  expect_error_naming([&] { EncoderCorruption(kJoints, two, 1); }, "quantisation");
  EncoderCorruption enc(kJoints, {}, 1);
  std::vector<double> a(3, 0.0), out(3);
  enc.corrupt(1.0, 0.001, a, {}, out);
  expect_error_naming([&] { enc.corrupt(0.5, 0.001, a, {}, out); }, "time stamps");
  expect_error_naming([&] { enc.corrupt(2.0, -0.1, a, {}, out); }, "dt_s");
}

}  // namespace
}  // namespace arttrack::sim
