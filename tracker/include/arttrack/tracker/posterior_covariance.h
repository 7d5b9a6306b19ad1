// The covariance the tracker reports: a full Gaussian over the quantities
// the depth images inform, kept beside the per-joint filters
// (docs/accuracy.md, "Consistency").
//
// The joint filters (joint_filter.h) hold one 2-D Gaussian per joint, and
// the particle filter's moments collapse (image_information.h says why), so
// their variances say far less than what is known: the truth fell within
// their 2 sigma in under 10% of samples. Their means are good; this module
// only estimates how good, the way an extended Kalman filter would, with
// the particle filter's mean as the linearisation point:
//   states x: per DOF the slow quantity the image informs:
//     kBias   an encoder joint's bias b (its angle is a = q - b, so the
//             angle error is minus the bias error, plus encoder noise);
//     kAngle  a DOF without encoder (camera offsets, vision-only angles).
//   predict over dt: a bias follows its Ornstein-Uhlenbeck process
//     (x_i x_j scaled by phi_i phi_j, phi = exp(-k dt), plus
//     sigma_b^2 (1 - phi^2) / (2k)), an angle its random walk (+ sigma_a^2 dt);
//   update with an image's information I about the DOFs' angles
//     (image_information.h), scaled by `information_scale` (neighbouring
//     pixels' errors are correlated, so the image is worth fewer pixels than
//     it has): with D = diag(-1 for biases, +1 for angles),
//     P <- (P^-1 + s D I D)^-1 = (Id + P s D I D)^-1 P.
// Encoder readings between images are taken to carry no information about
// the bias (the angle's diffusion is orders of magnitude faster), which errs
// on the side of a larger variance.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace arttrack {

class PosteriorCovariance {
 public:
  enum class Kind { kBias, kAngle };
  struct State {
    int dof = 0;  // the model's DOF the state belongs to
    Kind kind = Kind::kAngle;
    double decay_per_s = 0;  // k of a bias's OU process (0: a random walk)
    double rate_var = 0;     // sigma^2 per second of its diffusion
  };

  PosteriorCovariance() = default;
  explicit PosteriorCovariance(std::vector<State> states);

  const std::vector<State>& states() const { return states_; }
  int size() const { return int(states_.size()); }
  bool started() const { return started_; }
  double time_s() const { return time_s_; }

  // Starts (or restarts) from independent variances, one per state, at time_s.
  void reset(const Eigen::VectorXd& variances, double time_s);
  // Forgets what is known about state i: its row and column are zeroed and
  // its variance set (a state a search has just moved).
  void restart_state(int i, double variance);
  // Moves the covariance to time_s (>= time_s()).
  void predict_to(double time_s);
  // Folds in an image's information about the states' DOFs (their angles),
  // in states() order, times `information_scale`.
  void update(const Eigen::MatrixXd& angle_information, double information_scale);
  // Variance of state i after predicting to time_s (>= time_s()), without
  // changing the covariance.
  double variance_at(int i, double time_s) const;
  // The covariance of the states' DOFs' angle errors (D P D), without encoder noise.
  Eigen::MatrixXd angle_covariance() const;
  const Eigen::MatrixXd& covariance() const { return P_; }

 private:
  std::vector<State> states_;
  Eigen::VectorXd sign_;  // D's diagonal
  Eigen::MatrixXd P_, scratch_, identity_;
  double time_s_ = 0;
  bool started_ = false;
};

}  // namespace arttrack
