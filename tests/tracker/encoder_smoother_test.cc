#include "arttrack/tracker/internal/encoder_smoother.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"

namespace arttrack {
namespace {

constexpr double kDt = 1e-3;                    // 1 kHz, as the encoders
constexpr double kSigmaQ = 0.057 * kRadPerDeg;  // the default encoder noise
constexpr double kSigmaV = 20 * kRadPerDeg;     // the default rate diffusion

// The RMS error of the smoothed and the raw readings of a joint moving at
// `rate` plus `accel` t^2 / 2, from 1 s to 3 s (past the start).
struct Errors {
  double smoothed = 0, raw = 0, mean_smoothed = 0;
};
Errors track(double rate, double accel, double sigma_v, unsigned seed) {
  EncoderSmoother s(std::vector<double>{kSigmaQ * kSigmaQ}, std::vector<char>{1}, sigma_v);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, kSigmaQ);
  Errors e;
  int n = 0;
  for (int i = 0; i <= 3000; ++i) {
    const double t = i * kDt, truth = 0.3 + rate * t + accel * t * t / 2;
    double reading[1] = {truth + noise(rng)};
    const double raw = reading[0];
    s.smooth(kDt, reading);
    if (t < 1) continue;
    e.smoothed += (reading[0] - truth) * (reading[0] - truth);
    e.mean_smoothed += reading[0] - truth;
    e.raw += (raw - truth) * (raw - truth);
    ++n;
  }
  e.smoothed = std::sqrt(e.smoothed / n);
  e.raw = std::sqrt(e.raw / n);
  e.mean_smoothed /= n;
  return e;
}

// A joint at constant rate is followed without lag, its reading's noise
// averaged: the steady-state error is a fraction of the encoder's, and it
// matches the filter's own variance.
TEST(EncoderSmoother, AveragesTheNoiseOfAJointAtConstantRate) {
  const Errors e = track(0.5, 0, kSigmaV, 1);
  EXPECT_NEAR(e.raw, kSigmaQ, 0.05 * kSigmaQ);
  EXPECT_LT(e.smoothed, 0.45 * e.raw);
  EXPECT_LT(std::abs(e.mean_smoothed), 0.05 * kSigmaQ);  // no lag at constant rate

  EncoderSmoother s(std::vector<double>{kSigmaQ * kSigmaQ}, std::vector<char>{1}, kSigmaV);
  double reading[1] = {0};
  for (int i = 0; i < 3000; ++i) s.smooth(kDt, reading);
  EXPECT_NEAR(std::sqrt(s.angle_var_rad2()[0]), e.smoothed, 0.15 * e.smoothed);
}

// Under a constant acceleration the lag is the white-acceleration model's,
// small against the encoder noise for an arm's accelerations, and a
// smaller rate diffusion averages more but lags more.
TEST(EncoderSmoother, LagsLittleBehindAnAcceleratingJoint) {
  const double accel = 100 * kRadPerDeg;  // 100 deg/s^2
  const Errors e = track(0, accel, kSigmaV, 2);
  EXPECT_LT(std::abs(e.mean_smoothed), 0.3 * kSigmaQ);
  EXPECT_LT(e.smoothed, 0.6 * e.raw);
  const Errors slow = track(0, accel, 0.1 * kSigmaV, 2);
  EXPECT_GT(std::abs(slow.mean_smoothed), 3 * std::abs(e.mean_smoothed));
}

// The first reading is taken whole; joints not smoothed pass unchanged.
TEST(EncoderSmoother, TakesTheFirstReadingAndPassesPrismaticJoints) {
  EncoderSmoother s(std::vector<double>{kSigmaQ * kSigmaQ, 1e-8}, std::vector<char>{1, 0}, kSigmaV);
  double readings[2] = {0.7, 0.02};
  s.smooth(123.0, readings);
  EXPECT_EQ(readings[0], 0.7);
  EXPECT_EQ(readings[1], 0.02);
  readings[0] = 0.8;
  readings[1] = 0.03;
  s.smooth(kDt, readings);
  EXPECT_GT(readings[0], 0.7);
  EXPECT_LT(readings[0], 0.8);
  EXPECT_EQ(readings[1], 0.03);
  EXPECT_EQ(s.rate_rad_per_s()[1], 0.0);
}

// A reading after a long gap is taken almost whole (the rate's diffusion
// has grown the angle's spread).
TEST(EncoderSmoother, AGapLetsTheReadingThrough) {
  EncoderSmoother s(std::vector<double>{kSigmaQ * kSigmaQ}, std::vector<char>{1}, kSigmaV);
  double reading[1] = {0};
  for (int i = 0; i < 100; ++i) s.smooth(kDt, reading);
  reading[0] = 0.5;
  s.smooth(1.0, reading);
  EXPECT_NEAR(reading[0], 0.5, 1e-3);
}

TEST(EncoderSmoother, BadInputIsAnError) {
  const std::vector<double> var{kSigmaQ * kSigmaQ};
  const std::vector<char> on{1};
  EXPECT_THROW(EncoderSmoother(var, std::vector<char>{1, 1}, kSigmaV), InputError);
  EXPECT_THROW(EncoderSmoother(var, on, 0.0), InputError);
  EXPECT_THROW(EncoderSmoother(var, on, NAN), InputError);
  EXPECT_THROW(EncoderSmoother(std::vector<double>{0.0}, on, kSigmaV), InputError);
  EncoderSmoother s(var, on, kSigmaV);
  double two[2] = {0, 0};
  EXPECT_THROW(s.smooth(kDt, two), InputError);
  double one[1] = {0};
  s.smooth(kDt, one);
  EXPECT_THROW(s.smooth(-kDt, one), InputError);
  EXPECT_THROW(s.smooth(INFINITY, one), InputError);
  EXPECT_THROW(s.set_encoder_var(0, 0.0), InputError);
  EXPECT_THROW(s.set_encoder_var(0, NAN), InputError);
  EXPECT_THROW(s.set_encoder_var(1, 1e-6), InputError);  // no joint 1
}

}  // namespace
}  // namespace arttrack
