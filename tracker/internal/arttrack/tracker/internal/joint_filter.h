// Joint encoder filtering: one 2-state Kalman filter per joint over (angle a,
// encoder bias b), all joints of the robot in one structure-of-arrays bank
// (paper Sec. "Filtering joint measurements", Eq. (9);
// docs/method.md "Joint filter"). Virtual (camera) joints live in the same
// bank as 1-D random walks without encoder and bias.
//
// Models, every noise in continuous time so parameters keep their meaning at
// any joint rate and with variable time steps dt (seconds):
//   encoder  q = a + b + N(0, sigma_q^2)                         (Eq. (3))
//   angle    a(t+dt) = a(t) + N(0, sigma_a^2 dt)                 (Eq. (4))
//   bias     Ornstein-Uhlenbeck  db = -k b dt + sigma_b dW,  k = ln(1/c):
//            b(t+dt) = c^dt b(t) + N(0, sigma_b^2 (1 - c^(2 dt)) / (2k))
// The bias step is the EXACT discretisation of that process. It generalises
// the paper's Eq. (5), b(t+dt) = c^dt b(t) + N(0, dt sigma_b^2) (both in
// docs/method.md "Joint filter"), which is its first-order form for small
// k dt. The difference shows in the stationary variance: here
// sigma_b^2 / (2 ln(1/c)) whatever the rate, against
// dt sigma_b^2 / (1 - c^(2 dt)) in the paper's Eq. (8), which tends to the
// same value as dt -> 0 but drifts with dt.
// Choose c and sigma_b so that the stationary standard deviation covers the
// largest bias expected (stationary_bias_std_rad()).
//
// Model/data split: JointFilterModel (names, noises; immutable, shareable)
// and JointBelief (means and covariances; what the filter changes). Encoder
// joints come first in the bank (indices [0, num_encoder_joints())), virtual
// joints after them. Angles in radians (metres for prismatic virtual joints).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "arttrack/tracker/internal/gaussian_fold.h"
#include "arttrack/tracker/joint_filter_params.h"
#include "arttrack/tracker/units.h"

namespace arttrack {

// The constant part of the bank: joint names and their noises, stored as
// flat per-joint arrays for the filter loops. Only an encoder's noise may
// change, to what its readings show (set_encoder_var).
class JointFilterModel {
 public:
  // Encoder joints (with their parameters, same order) then virtual joints.
  // Throws InputError naming the joint for a bad value
  // (JointFilterParams::validate; a virtual joint's negative diffusion or
  // initial std that is not positive) or a duplicate name.
  JointFilterModel(std::vector<std::string> encoder_joints,
                   std::vector<JointFilterParams> encoder_params,
                   std::vector<std::string> virtual_joints = {},
                   std::vector<VirtualJointParams> virtual_params = {});

  int num_joints() const { return int(names_.size()); }
  int num_encoder_joints() const { return num_encoder_; }
  int num_virtual_joints() const { return num_joints() - num_encoder_; }
  // All names, encoder joints first.
  const std::vector<std::string>& joint_names() const { return names_; }
  // Bank index of a joint, or -1.
  int index_of(std::string_view name) const;
  bool is_virtual(int j) const { return j >= num_encoder_; }

  // Flat per-joint constants (bank order), continuous time.
  std::span<const double> encoder_var_rad2() const { return var_q_; }    // sigma_q^2
  std::span<const double> angle_rate_var() const { return rate_a_; }     // sigma_a^2, per s
  std::span<const double> bias_rate_var() const { return rate_b_; }      // sigma_b^2, per s
  std::span<const double> bias_decay_rate_per_s() const { return k_; }   // k = ln(1/c)
  std::span<const double> initial_var_a() const { return init_var_a_; }  // virtual joints
  std::span<const double> initial_var_b() const { return init_var_b_; }  // stationary

  // Encoder joint j's sigma_q^2 from now on (> 0 and finite, else
  // InputError naming the joint): the tracker raises it to the noise the
  // readings show (encoder_noise_meter.h).
  void set_encoder_var(int j, double var_rad2);

 private:
  std::vector<std::string> names_;
  int num_encoder_ = 0;
  std::vector<double> var_q_, rate_a_, rate_b_, k_, init_var_a_, init_var_b_;
};

// The belief: one Gaussian over (a, b) per joint, structure of arrays in
// bank order. Virtual joints and joints without bias keep b = 0 with zero
// variance and covariance.
struct JointBelief {
  std::vector<double> mean_a, mean_b, var_a, cov_ab, var_b;

  int size() const { return int(mean_a.size()); }
  AngleBiasGaussian joint(int j) const {
    return {mean_a[j], mean_b[j], var_a[j], cov_ab[j], var_b[j]};
  }
  void set_joint(int j, const AngleBiasGaussian& g);
};

// The belief after the first encoder reading: for encoder joints the exact
// posterior given q with bias prior N(0, stationary variance) and a flat
// angle prior (a = q, var_a = sigma_q^2 + var_b, cov_ab = -var_b); virtual
// joints at 0 with their initial variance. Throws InputError for a size
// mismatch or a non-finite reading (naming the joint).
JointBelief initial_joint_belief(const JointFilterModel& model,
                                 std::span<const double> encoder_rad);

// Prediction over dt_s >= 0 seconds, all joints. Throws InputError for a
// negative or non-finite dt_s. Allocation-free.
void predict_joints(const JointFilterModel& model, double dt_s, JointBelief& belief);

// Measurement update with one reading per encoder joint (bank order, size
// num_encoder_joints()), Joseph form. Throws InputError (naming the joint)
// for a non-finite reading, before changing anything. Allocation-free.
void update_encoders(const JointFilterModel& model, std::span<const double> encoder_rad,
                     JointBelief& belief);

// predict_joints then update_encoders in one pass over the bank: the 1 kHz
// step, and the re-filtering loop after a delayed image.
void filter_joints(const JointFilterModel& model, double dt_s, std::span<const double> encoder_rad,
                   JointBelief& belief);

// Folds image-based angle posteriors N(mean_a[j], var_a[j]) (one per bank
// joint) into the belief, keeping each joint's p(b | a) (gaussian_fold.h).
void fold_angle_posteriors(std::span<const double> mean_a, std::span<const double> var_a,
                           JointBelief& belief);

}  // namespace arttrack
