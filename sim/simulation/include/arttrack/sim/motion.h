// Commanded joint trajectories: the targets the simulator's position
// actuators follow (position for the kp term, velocity for the kv term).
//
// A JointTrajectory covers a fixed list of joints (angles in rad, times in s)
// and is the sum of parts, each acting on named joints:
//   target(t) = clamp(home + sum over parts of displacement_part(t), limits)
// A part's displacement is its own absolute target minus the home angle, so
// a joint moved by one part alone follows that part's values exactly, and
// parts on the same joint add (e.g. random motion around an out-of-view
// configuration). Where the sum leaves the joint limits it is clamped and the
// velocity there is 0.
//
// Parts: sinusoids (SinusoidMotion), waypoints with minimum-jerk (quintic)
// interpolation (WaypointMotion), smooth random motion from a seeded
// generator (RandomMotion), and leaving the camera's view and coming back
// (OutOfViewMotion, built on waypoints).
//
// Parameter structs are filled from scenario YAML; validate() throws
// arttrack::InputError naming the field when a value is impossible.
#pragma once

#include <cstdint>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace arttrack::sim {

// Range a joint may be commanded to, rad.
struct JointLimit {
  double lower_rad = -std::numeric_limits<double>::infinity();
  double upper_rad = std::numeric_limits<double>::infinity();
};

// q_j(t) = centre_j + e(t) amplitude sin(2 pi frequency t + phase) on every
// listed joint, with e(t) a minimum-jerk fade-in from 0 to 1 over fade_in_s
// (e = 1 when fade_in_s is 0).
struct SinusoidMotion {
  // Joints this part moves.
  std::vector<std::string> joints;
  // Peak deviation from the centre, rad (may be negative: opposite phase).
  double amplitude_rad = 0.2;
  // Oscillation frequency, Hz (> 0).
  double frequency_hz = 0.2;
  // Phase at t = 0 (after the fade-in envelope), rad.
  double phase_rad = 0.0;
  // Centre per listed joint, rad; empty: the home configuration.
  std::vector<double> centre_rad;
  // Duration of the fade-in of the whole displacement (amplitude and centre
  // shift), s; 0: the sinusoid starts at full amplitude at t = 0.
  double fade_in_s = 0.0;

  void validate() const;
};

// Absolute joint targets at given times, interpolated rest-to-rest with the
// minimum-jerk quintic 10 s^3 - 15 s^4 + 6 s^5 between consecutive waypoints
// (C2: velocity and acceleration are 0 at every waypoint, so the motion stops
// there). Before the first waypoint the first is held, after the last the
// last is held. Each waypoint is reached exactly at its time.
struct WaypointMotion {
  // Joints this part moves.
  std::vector<std::string> joints;
  // Waypoint times, s, strictly increasing, >= 0.
  std::vector<double> times_s;
  // One vector of joint angles per waypoint, in the order of `joints`, rad.
  std::vector<std::vector<double>> positions_rad;

  void validate() const;
};

// Smooth random motion: on each joint a sum of num_components sinusoids with
// equal weights, random frequencies (ratios uniform in [0.5, 1.5]) and random
// phases, drawn from the generator given to JointTrajectory::add. The
// frequencies are scaled so that the RMS joint speed is
// speed_scale * base_speed_rad_per_s at the full amplitude.
//
// Bounds: the displacement around the centre never exceeds amplitude_rad.
// The centre is the home angle, moved inside [lower + margin + A,
// upper - margin - A]; where the joint's range is narrower than 2 (A +
// margin), A shrinks to fit. So the motion stays margin_rad inside the
// limits; the fade-in blends from home to it without a jump at t = 0.
struct RandomMotion {
  // Joints this part moves.
  std::vector<std::string> joints;
  // Largest deviation from the centre, rad (> 0).
  double amplitude_rad = 0.3;
  // 1: slow (RMS speed base_speed_rad_per_s), 3: fast (the paper's "++").
  double speed_scale = 1.0;
  // RMS joint speed at speed_scale 1 and full amplitude, rad/s.
  double base_speed_rad_per_s = 0.2;
  // Distance kept from the joint limits, rad (>= 0).
  double margin_rad = 0.05;
  // Number of sinusoids summed per joint (>= 1); more looks less periodic.
  int num_components = 4;
  // Minimum-jerk fade-in from home to the random motion, s (>= 0).
  double fade_in_s = 1.0;

  void validate() const;
};

// Leave the camera's view and come back: from leave_s the listed joints move
// (minimum jerk, move_duration_s) from home to out_of_view_rad, stay there,
// and from return_s move back to home in the same time. Before leave_s and
// after return_s + move_duration_s the displacement is 0.
struct OutOfViewMotion {
  // Joints this part moves.
  std::vector<std::string> joints;
  // Out-of-view configuration in the order of `joints`, rad (chosen by the
  // caller so the arm is outside the camera's field of view).
  std::vector<double> out_of_view_rad;
  // Time the move away starts, s (>= 0).
  double leave_s = 5.0;
  // Time the move back starts, s (>= leave_s + move_duration_s).
  double return_s = 15.0;
  // Duration of each move, s (> 0).
  double move_duration_s = 2.0;

  void validate() const;
};

// Target joint angles over time for a fixed list of joints. Built once (add
// parts), then evaluated without allocating; evaluation is const and
// thread-safe.
class JointTrajectory {
 public:
  // joint_names: the joints the trajectory covers, in output order.
  // home_rad: the configuration with all displacements 0 (same order).
  // limits: per joint (same order). Throws InputError on size mismatch,
  // duplicate names, lower > upper or home outside the limits.
  JointTrajectory(std::vector<std::string> joint_names, std::vector<double> home_rad,
                  std::vector<JointLimit> limits);

  // Add a part. Each validates its parameters and throws InputError on an
  // unknown joint, a joint listed twice, or (waypoints) a target outside the
  // joint limits. RandomMotion draws its frequencies and phases from `rng`.
  void add(const SinusoidMotion& part);
  void add(const WaypointMotion& part);
  void add(const RandomMotion& part, std::mt19937_64& rng);
  void add(const OutOfViewMotion& part);

  const std::vector<std::string>& joint_names() const { return joint_names_; }
  std::size_t num_joints() const { return joint_names_.size(); }
  const std::vector<double>& home_rad() const { return home_rad_; }
  const std::vector<JointLimit>& limits() const { return limits_; }
  // Index of a joint; throws InputError naming it if it is not covered.
  std::size_t joint_index(std::string_view name) const;

  // Target angles at time t_s, rad (q_out.size() == num_joints()).
  void position(double t_s, std::span<double> q_out) const;
  // Target velocities at time t_s, rad/s: the analytic derivative of
  // position(), 0 where the target is clamped at a limit.
  void velocity(double t_s, std::span<double> qd_out) const;
  // Allocating conveniences.
  std::vector<double> position(double t_s) const;
  std::vector<double> velocity(double t_s) const;

 private:
  // Every part is reduced to terms of these three kinds, kept per joint.
  struct SineTerm {  // e(t) (offset + amplitude sin(omega t + phase))
    double offset_rad, amplitude_rad, omega_rad_per_s, phase_rad, fade_in_s;
  };
  struct WaypointTerm {  // minimum-jerk through (times, values), minus home
    std::vector<double> times_s, values_rad;
  };
  struct RandomTerm {  // e(t) (offset + sum_k weight_k sin(omega_k t + phase_k))
    double offset_rad, fade_in_s;
    std::vector<double> weight_rad, omega_rad_per_s, phase_rad;
  };
  struct JointTerms {
    std::vector<SineTerm> sines;
    std::vector<WaypointTerm> waypoints;
    std::vector<RandomTerm> randoms;
  };

  std::vector<std::size_t> resolve(const std::vector<std::string>& joints,
                                   std::string_view part) const;
  // Clamped target of joint j at t_s and its time derivative.
  void evaluate(std::size_t j, double t_s, double& q_rad, double& qd_rad_per_s) const;

  std::vector<std::string> joint_names_;
  std::vector<double> home_rad_;
  std::vector<JointLimit> limits_;
  std::vector<JointTerms> terms_;  // per joint
};

}  // namespace arttrack::sim
