#include "arttrack/tracker/internal/encoder_noise_meter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"

namespace arttrack {
namespace {

// Joint 0 moves as a servoed joint does (a sine of 0.5 rad at 1 Hz: up to
// 20 rad/s^2) with white noise `sigma` and a bias that ramps by `ramp_rad`
// per second; joint 1 has no encoder. Readings at 1 kHz, each stamp
// jittered by up to 0.2 ms; the meter's estimate for joint 0 after
// `seconds`.
double measured(double sigma, double ramp_rad, double seconds, unsigned seed) {
  EncoderNoiseMeter meter(std::vector<char>{1, 0}, 2.0);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0, 1);  // times sigma: sigma may be 0
  std::uniform_real_distribution<double> jitter(-2e-4, 2e-4);
  for (int i = 0; i <= int(seconds * 1000); ++i) {
    const double t = 1e-3 * i + jitter(rng);
    const double truth = 0.5 * std::sin(2 * M_PI * t), bias = 0.15 + ramp_rad * t;
    meter.add(t, std::vector<double>{truth + bias + sigma * unit(rng), 0.0});
  }
  EXPECT_TRUE(std::isnan(meter.noise_std(1)));  // no encoder
  return meter.noise_std(0);
}

// The white noise of a moving joint is found within a few percent, on an
// uneven clock, whatever the motion and the bias (a constant one and a
// ramp cancel in the divided difference).
TEST(EncoderNoiseMeter, FindsTheWhiteNoiseOfAMovingJoint) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    const double sigma = 0.057 * kRadPerDeg;  // the default encoder noise
    EXPECT_NEAR(measured(sigma, 0, 4, seed), sigma, 0.05 * sigma);
    EXPECT_NEAR(measured(4 * sigma, 0, 4, seed), 4 * sigma, 0.05 * 4 * sigma);
    EXPECT_NEAR(measured(sigma, 0.2, 4, seed), measured(sigma, 0, 4, seed), 1e-3 * sigma);
  }
  // Without noise, the motion alone reads as (almost) none: its jerk over
  // 1 ms moves the difference by 1e-8 rad at most.
  EXPECT_LT(measured(0, 0, 4, 1), 1e-7);
}

// Before 100 differences there is no estimate; a reading at the time of
// the previous one is ignored; a wrong number of readings is an error
// naming both counts.
TEST(EncoderNoiseMeter, WaitsForEnoughReadingsAndChecksItsInput) {
  EncoderNoiseMeter meter(std::vector<char>{1}, 2.0);
  const int first = EncoderNoiseMeter::kMinDifferences + 2;  // readings without an estimate
  for (int i = 0; i < first; ++i) {
    meter.add(1e-3 * i, std::vector<double>{i % 2 ? 1e-3 : -1e-3});
    EXPECT_TRUE(std::isnan(meter.noise_std(0))) << i;
  }
  meter.add(1e-3 * first, std::vector<double>{first % 2 ? 1e-3 : -1e-3});
  const double estimate = meter.noise_std(0);
  EXPECT_TRUE(std::isfinite(estimate));
  // Alternating +-1 mrad: |q3 - 3 q2 + 3 q1 - q0| / sqrt(20) = 8 mrad /
  // sqrt(20), as Gaussian noise of that times sqrt(pi / 2) would give.
  EXPECT_NEAR(estimate, 8e-3 / std::sqrt(20.0) * std::sqrt(M_PI / 2), 1e-12);
  meter.add(1e-3 * first, std::vector<double>{5.0});  // the same time: ignored
  EXPECT_EQ(meter.noise_std(0), estimate);
  EXPECT_THROW(meter.add(1.0, std::vector<double>{0.0, 0.0}), InputError);
  EXPECT_THROW(EncoderNoiseMeter(std::vector<char>{1}, 0.0), InputError);
  EXPECT_TRUE(std::isnan(meter.noise_std(1)));  // out of range
}

}  // namespace
}  // namespace arttrack
