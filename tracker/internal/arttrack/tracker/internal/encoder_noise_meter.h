// Each encoder's white noise as its readings show it (TrackingHealth::
// encoder_noise_measured_rad; docs/accuracy.md, "Encoders noisier than
// configured"). The tracker weighs every reading by the configured
// encoder_noise (joint_filter.h) and smooths with it (encoder_smoother.h);
// a real encoder may be noisier than the user thinks, and then the angles
// carry the difference unseen.
//
// A servoed joint moves smoothly, so over a few milliseconds its readings
// are a straight line plus the noise. The second difference of three
// readings at times t0 < t1 < t2, with r = (t2 - t1) / (t1 - t0),
//   d = q2 - q1 - r (q1 - q0),
// cancels any constant rate and leaves the noise with variance
// sigma^2 (1 + (1 + r)^2 + r^2) (6 sigma^2 at an even clock), plus the
// acceleration times (t2 - t1)(t2 - t0) / 2: at 1 kHz, 10 rad/s^2 adds
// 1e-5 rad, against 1e-3 rad of noise. Each joint's |d|, normalised by that
// factor's square root, is averaged over time_constant_s; for Gaussian
// noise E|x| = sigma sqrt(2 / pi), and the mean of absolute values is less
// moved by one glitch than the mean of squares. A bias, or its drift, is
// in all three readings alike and cancels.
//
// Setup: the number of joints and the time constant. Workspace: per joint
// the last two readings and the running average (sized at construction:
// allocation-free after it). Internal to the tracker (tracker/internal:
// not installed). Not thread-safe: the joint thread's.
#pragma once

#include <limits>
#include <span>
#include <vector>

namespace arttrack {

class EncoderNoiseMeter {
 public:
  // Readings before a joint's estimate is given (NaN before): enough that
  // the average is within about 10% of its value.
  static constexpr int kMinReadings = 100;

  // `measured[j]`: whether joint j has an encoder (else always NaN).
  // time_constant_s > 0.
  EncoderNoiseMeter(std::span<const char> measured, double time_constant_s);

  // One reading of every joint at time_s (increasing; a reading at the same
  // time as the previous one is ignored, as its second difference is
  // undefined).
  void add(double time_s, std::span<const double> readings);

  // Joint j's white-noise standard deviation, in the readings' unit; NaN
  // for a joint without encoder or before kMinReadings second differences.
  double noise_std(int j) const;
  int num_joints() const { return int(measured_.size()); }

 private:
  std::vector<char> measured_;
  double time_constant_s_;
  int readings_ = 0;  // readings taken, at distinct times
  double t0_s_ = std::numeric_limits<double>::quiet_NaN(), t1_s_ = t0_s_;
  std::vector<double> q0_, q1_;   // the two previous readings
  std::vector<double> mean_abs_;  // running average of |d| / sqrt(factor)
  double weight_ = 0;             // the average's total weight (it starts from 0)
};

}  // namespace arttrack
