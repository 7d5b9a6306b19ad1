// Each encoder's white noise as its readings show it (TrackingHealth::
// encoder_noise_measured_rad; docs/accuracy.md, "Encoders noisier than
// configured"). The tracker weighs every reading by the configured
// encoder_noise (joint_filter.h) and smooths with it (encoder_smoother.h);
// a real encoder may be noisier than the user thinks, and then the angles
// carry the difference unseen.
//
// A servoed joint moves smoothly, so over a few milliseconds its readings
// are a parabola plus the noise. The third divided difference of four
// readings at times t0 < t1 < t2 < t3,
//   d = sum_i w_i q_i,  w_i = 1 / prod_{j != i} (t_i - t_j),
// cancels any angle, rate and acceleration (and a bias, constant or
// ramping: it is in all four readings alike) whatever the clock, and
// leaves the noise with variance sigma^2 sum_i w_i^2; d / |w| has variance
// sigma^2 ((q3 - 3 q2 + 3 q1 - q0) / sqrt(20) at an even clock). The jerk
// adds about jerk dt^3 / 6: 2e-8 rad at 1 kHz and 100 rad/s^3, 2e-5 rad at
// 100 Hz, against 1e-3 rad of noise. Each joint's |d| / |w| is averaged
// over time_constant_s (weighted by the time between readings); for
// Gaussian noise E|x| = sigma sqrt(2 / pi), and the mean of absolute
// values is less moved by one glitch than the mean of squares.
//
// Setup: the number of joints and the time constant. Workspace: per joint
// the last three readings and the running average (sized at construction:
// allocation-free after it). Internal to the tracker (tracker/internal:
// not installed). Not thread-safe: the joint thread's.
#pragma once

#include <limits>
#include <span>
#include <vector>

namespace arttrack {

class EncoderNoiseMeter {
 public:
  // Differences averaged before a joint's estimate is given (NaN before):
  // enough that the average is within about 10% of its value.
  static constexpr int kMinDifferences = 100;
  // Differences after which the estimate is within a few percent, enough to
  // act on (encoder_noise.from_readings): at kMinDifferences an encoder as
  // noisy as configured read 25% over for a moment (docs/accuracy.md,
  // "Encoders noisier than configured").
  static constexpr int kSettledDifferences = 1000;

  // `measured[j]`: whether joint j has an encoder (else always NaN).
  // time_constant_s > 0.
  EncoderNoiseMeter(std::span<const char> measured, double time_constant_s);

  // One reading of every joint at time_s (increasing; a reading at the same
  // time as the previous one is ignored, as its divided difference is
  // undefined).
  void add(double time_s, std::span<const double> readings);

  // Joint j's white-noise standard deviation, in the readings' unit; NaN
  // for a joint without encoder or before kMinDifferences differences.
  double noise_std(int j) const;
  int num_joints() const { return int(measured_.size()); }
  // Differences taken so far (one per reading from the fourth on).
  int differences() const { return readings_ < 3 ? 0 : readings_ - 3; }

 private:
  std::vector<char> measured_;
  double time_constant_s_;
  int readings_ = 0;  // readings taken, at distinct times
  // The three previous readings' times (oldest first) and values per joint.
  double t_s_[3] = {};
  std::vector<double> q_[3];
  std::vector<double> mean_abs_;  // running average of |d| / |w|
  double weight_ = 0;             // the average's total weight (it starts from 0)
};

}  // namespace arttrack
