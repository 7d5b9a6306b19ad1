// What a real robot's joint encoders report: the true angle plus a bias that
// the encoder cannot see, plus white noise, quantised.
//
//   reading = quantise(angle + bias(t) + N(0, sigma^2))
//   bias(t) = offset + alternating_step(t) + stretch(t)
//
// bias(t) is the ground truth the tracker's bias estimate is scored against
// (paper Eq. (3): q = a + b + noise). Its parts:
//   offset            constant, rad (the paper's 8.6 degrees on every joint);
//   alternating step  +A held, a cosine ramp to -A over ramp_time, -A held,
//                     a ramp back to +A, ... with period period_s (the paper's
//                     "time-varying bias", A = 5 degrees);
//   cable stretch     compliance x transmitted torque through a first-order
//                     lag (time constant tau), like the ARM robot's cable
//                     drives whose encoders sit at the motors.
//
// Components are set per group of joints and compose: offsets add, noise
// variances add, and at most one group may set the step, the cable stretch or
// the quantisation of any one joint.
#pragma once

#include <cstdint>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace arttrack::sim {

// Corruption of a group of joints. Every component is off at its default.
// The _rad values are metres for a prismatic joint (and compliance metres
// per newton), as the simulator's joint values are: a scenario gives a
// group's prismatic joints keys in metres (scenario.h).
struct EncoderGroupCorruption {
  // Joints of the group; empty: every joint.
  std::vector<std::string> joints;
  // Constant bias, rad.
  double offset_rad = 0.0;
  // Alternating smooth steps: amplitude A, rad (the bias starts at +A; a
  // negative A starts at -A); 0 turns them off.
  double step_amplitude_rad = 0.0;
  // Full period of the steps (+A, ramp, -A, ramp), s (> 0).
  double step_period_s = 20.0;
  // Duration of each ramp between +A and -A, s, in [0, period / 2]; 0 is an
  // abrupt step.
  double step_ramp_time_s = 1.0;
  // Cable stretch: bias = compliance x torque transmitted to the joint (the
  // actuator's torque on the link, N m), lagged. 0 turns it off.
  double compliance_rad_per_Nm = 0.0;
  // Time constant of the stretch's first-order lag, s (>= 0; 0: no lag).
  double stretch_time_constant_s = 0.05;
  // White noise standard deviation, rad (>= 0).
  double noise_sigma_rad = 0.0;
  // Quantisation step: readings are rounded to the nearest multiple, rad
  // (>= 0; 0: not quantised).
  double resolution_rad = 0.0;

  void validate() const;
};

// Corruption of all encoders: a list of groups.
struct EncoderCorruptionParams {
  std::vector<EncoderGroupCorruption> groups;

  void validate() const;
};

// The alternating smooth step of amplitude A at time t_s, rad: +A on
// [0, P/2 - r), A cos(pi (t - (P/2 - r)) / r) on [P/2 - r, P/2), -A on
// [P/2, P - r), a ramp back to +A on [P - r, P), periodic in P.
double alternating_step_rad(double t_s, double amplitude_rad, double period_s, double ramp_time_s);

// Corrupts true joint angles into encoder readings, one joint vector per
// call. State: the cable stretch lag and the noise generator; not
// thread-safe (one instance per simulated robot).
class EncoderCorruption {
 public:
  // joint_names: the joints readings are produced for, in order. Throws
  // InputError for invalid params, unknown joint names in a group, or two
  // groups setting the step, stretch or quantisation of the same joint.
  EncoderCorruption(std::vector<std::string> joint_names, const EncoderCorruptionParams& params,
                    std::uint64_t seed);

  // Readings at time t_s after a step of dt_s seconds since the previous
  // call. true_angles and readings_out have one value per joint (rad);
  // load_torques_Nm too, or is empty (zero torque). The stretch lag treats
  // the torque as constant over the step (exact discretisation,
  // b += (1 - exp(-dt / tau)) (compliance torque - b)), so its step response
  // is 1 - exp(-t / tau) at any dt; it starts unstretched. Throws InputError
  // if t_s decreases or dt_s is negative.
  void corrupt(double t_s, double dt_s, std::span<const double> true_angles,
               std::span<const double> load_torques_Nm, std::span<double> readings_out);

  // True bias per joint at the last corrupt() time (0 before the first), rad:
  // offset + step + stretch, without noise or quantisation error.
  std::span<const double> bias_rad() const { return bias_rad_; }
  const std::vector<std::string>& joint_names() const { return joint_names_; }

 private:
  struct JointCorruption {
    double offset_rad = 0.0;
    double step_amplitude_rad = 0.0, step_period_s = 1.0, step_ramp_time_s = 0.0;
    double compliance_rad_per_Nm = 0.0, stretch_time_constant_s = 0.0;
    double noise_sigma_rad = 0.0;
    double resolution_rad = 0.0;
  };

  std::vector<std::string> joint_names_;
  std::vector<JointCorruption> joints_;
  std::vector<double> stretch_rad_;  // lag state per joint
  std::vector<double> bias_rad_;
  double last_t_s_ = -std::numeric_limits<double>::infinity();
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace arttrack::sim
