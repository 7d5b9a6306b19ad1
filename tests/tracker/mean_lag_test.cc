// MeanLag (tracker/internal): the reported variance a still-moving mean
// adds, against the running averages' closed form.
#include "arttrack/tracker/internal/mean_lag.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

constexpr double kLagImagePeriod_s = 1.0 / 30;

// Feeds `means_at(t)` at 30 Hz from t = 0 up to and including end_s.
template <typename MeansAt>
void feed_at_30_hz(MeanLag& lag, double end_s, MeansAt means_at) {
  for (int k = 0; k * kLagImagePeriod_s <= end_s + 1e-9; ++k) {
    const double t = k * kLagImagePeriod_s;
    lag.update(t, means_at(t));
  }
}

// A mean that stands still adds nothing, however long.
TEST(MeanLag, AMeanStandingStillAddsNothing) {
  MeanLag lag({1, 1}, 2.0, 6.0);
  feed_at_30_hz(lag, 30.0, [](double) { return std::vector<double>{0.15, -0.02}; });
  EXPECT_EQ(lag.variance()[0], 0.0);
  EXPECT_EQ(lag.variance()[1], 0.0);
}

// A steady drift v: each average x <- x + a (m - x), a = 1 - exp(-dt /
// tau), trails the mean by v dt (1 - a) / a once settled, so the lag is v
// dt ((1 - a_slow) / a_slow - (1 - a_fast) / a_fast), about v (T - 0.2 s),
// and the variance scale times its square.
TEST(MeanLag, ASteadyDriftAddsTheAveragesClosedFormLag) {
  const double v = 0.01, scale = 2.0, T = 6.0;  // rad/s
  MeanLag lag({1}, scale, T);
  feed_at_30_hz(lag, 120.0, [&](double t) { return std::vector<double>{v * t}; });
  const double dt = kLagImagePeriod_s;
  const double a_fast = -std::expm1(-dt / MeanLag::kFastTimeConstant_s);
  const double a_slow = -std::expm1(-dt / T);
  const double expected = v * dt * ((1 - a_slow) / a_slow - (1 - a_fast) / a_fast);
  EXPECT_NEAR(lag.variance()[0], scale * expected * expected, 1e-7 * scale * expected * expected);
  EXPECT_NEAR(expected, v * (T - MeanLag::kFastTimeConstant_s), 1e-3 * v * T);
}

// The first kSettle_s after the first update: the acquisition's jumps and the
// particles' collapse after it are not counted.
TEST(MeanLag, TheFirstHalfSecondIsNotCounted) {
  MeanLag lag({1}, 2.0, 6.0);
  feed_at_30_hz(lag, 20.0, [](double t) { return std::vector<double>{t < 0.45 ? 0.3 * t : 0.14}; });
  EXPECT_EQ(lag.variance()[0], 0.0);
}

// A search moves a mean: restarted, its jump is not counted; left running,
// the same jump is a lag until the slow average catches up.
TEST(MeanLag, ARestartedStateForgetsItsJump) {
  MeanLag restarted({1}, 2.0, 6.0), running({1}, 2.0, 6.0);
  for (MeanLag* lag : {&restarted, &running})
    feed_at_30_hz(*lag, 5.0, [](double) { return std::vector<double>{0.0}; });
  restarted.restart(0);
  EXPECT_EQ(restarted.variance()[0], 0.0);
  for (MeanLag* lag : {&restarted, &running}) {
    for (int k = 1; k <= 30; ++k) lag->update(5.0 + k * kLagImagePeriod_s, std::vector{0.1});
  }
  EXPECT_EQ(restarted.variance()[0], 0.0);
  EXPECT_GT(running.variance()[0], 2.0 * 0.05 * 0.05);
}

// An untracked state (an angle that moves with the robot) and a scale of 0
// add nothing; a time that goes back counts as no time.
TEST(MeanLag, UntrackedOffAndBackwardTimesAddNothing) {
  MeanLag lag({0, 1}, 2.0, 6.0), off({1}, 0.0, 6.0);
  feed_at_30_hz(lag, 10.0, [](double t) { return std::vector<double>{t, 0.0}; });
  feed_at_30_hz(off, 10.0, [](double t) { return std::vector<double>{t}; });
  EXPECT_EQ(lag.variance()[0], 0.0);
  EXPECT_EQ(off.variance()[0], 0.0);
  lag.update(9.0, std::vector<double>{0.0, 0.0});
  EXPECT_TRUE(std::isfinite(lag.variance()[1]));
  EXPECT_EQ(lag.variance()[1], 0.0);
}

TEST(MeanLag, ABadSetupIsAnInputError) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(MeanLag({1}, -1.0, 6.0), InputError);
  EXPECT_THROW(MeanLag({1}, nan, 6.0), InputError);
  EXPECT_THROW(MeanLag({1}, 2.0, 0.1), InputError);
  EXPECT_THROW(MeanLag({1}, 2.0, nan), InputError);
  MeanLag lag({1, 1}, 2.0, 6.0);
  EXPECT_THROW(lag.update(0.0, std::vector<double>{0.0}), std::invalid_argument);
  EXPECT_THROW(lag.restart(2), std::invalid_argument);
}

}  // namespace
}  // namespace arttrack
