// Encoder smoothing: a constant-velocity Kalman filter over (angle, rate) on
// each revolute encoder's readings, ahead of the joint filter
// (TrackerConfig::EncoderSmoothing; docs/method.md "Joint filter";
// docs/accuracy.md "Encoders with noise").
//
// The joint filter's angle is a random walk fast enough to follow any
// motion (Eq. (4), sigma_a = 57.3 deg/sqrt(s)), so it takes each reading
// almost whole and the angle carries the reading's white noise; only an
// image pulls it back. A servoed joint moves smoothly: with its rate as a
// state, readings can be averaged without lagging behind the motion.
// Per joint, continuous time, variable dt:
//   angle a(t+dt) = a(t) + v(t) dt + (the rate's diffusion integrated)
//   rate  v(t+dt) = v(t) + N(0, sigma_v^2 dt)        (white acceleration)
//   reading q = a + N(0, sigma_q^2)
// with sigma_q the joint's encoder noise (JointFilterParams) and sigma_v
// the configured rate diffusion. The smoothed angle replaces the reading;
// the joint filter still counts sigma_q for it (its error is smaller, so
// the reported spread errs wide). The bias is the joint filter's: it is
// in every reading alike and the smoother passes it through.
//
// The first reading is taken whole, with an unknown rate
// (kInitialRateStdRadPerS); prismatic joints pass through unchanged.
//
// Internal to the tracker (not installed). Not thread-safe;
// allocation-free after construction.
#pragma once

#include <span>
#include <vector>

namespace arttrack {

class EncoderSmoother {
 public:
  // The standard deviation of the rate the first reading is taken with,
  // rad/s: an arm that is already moving when tracking starts.
  static constexpr double kInitialRateStdRadPerS = 2.0;

  // encoder_var_rad2[j]: joint j's encoder noise variance sigma_q^2;
  // smoothed[j]: whether joint j is smoothed (a revolute joint's reading),
  // else its readings pass unchanged. rate_diffusion_rad_per_s_per_sqrt_s:
  // sigma_v, > 0. Throws InputError for sizes that differ or a sigma_v or
  // variance that is not finite and positive.
  EncoderSmoother(std::span<const double> encoder_var_rad2, std::span<const char> smoothed,
                  double rate_diffusion_rad_per_s_per_sqrt_s);

  // Takes one reading of every joint, dt_s after the previous one (ignored
  // for the first), and replaces each smoothed joint's reading by its
  // smoothed angle. Throws InputError for a size that differs or a negative
  // or non-finite dt_s.
  void smooth(double dt_s, std::span<double> readings_rad);

  // Joint j's encoder noise variance from the next smooth() on (> 0, finite;
  // else InputError): the noise its readings show, where that is larger than
  // the configured one (encoder_noise_meter.h).
  void set_encoder_var(int j, double var_rad2);

  // Each joint's smoothed rate (rad/s) and the variance of its smoothed
  // angle (rad^2) after the last smooth(); 0 before the first.
  std::span<const double> rate_rad_per_s() const { return rate_; }
  std::span<const double> angle_var_rad2() const { return p_aa_; }

 private:
  std::vector<double> var_q_;
  std::vector<char> smoothed_;
  double rate_var_;  // sigma_v^2, (rad/s)^2 per s
  bool started_ = false;
  // Per joint: the smoothed angle, rate and their covariance.
  std::vector<double> angle_, rate_, p_aa_, p_av_, p_vv_;
};

}  // namespace arttrack
