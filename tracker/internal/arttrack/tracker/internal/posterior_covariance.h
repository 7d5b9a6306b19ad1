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
//
// Consider parameters: errors every image shares that the mean does not
// estimate, such as how far each real link is from the model's
// (image_information.h, link shifts), normalised to unit variance and
// constant in time. The tracker's mean is fitted as if they were zero, with
// the gain of the filter above (P, the nominal covariance); with them, an
// image's update moves the error e of the states as
//   e <- (Id - P+ J_xx) e - P+ J_xc c - (the gain times the pixel noise),
// J_xx, J_xc the image's information about the states and between them and
// the consider parameters c (signed by D, times s). The reported covariance
// is the covariance of that error (consider analysis, Joseph form):
//   Q_ee <- A Q_ee A^T + A Q_ec B^T + B Q_ce A^T + B B^T + P+ J_xx P+,
//   Q_ec <- A Q_ec + B,   with A = Id - P+ J_xx, B = -P+ J_xc,
// predicted like P. N images of one pose then leave the error the shared
// model error gives the fit, where P alone goes to zero as 1/N. P stays the
// filter's own weights (the refinement's prior). The last term is the
// gain times the pixels' noise as the weights assume it; an update may
// scale it (noise_scale) where the image's residuals show quieter pixels.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
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
  explicit PosteriorCovariance(std::vector<State> states, int num_consider = 0);

  const std::vector<State>& states() const { return states_; }
  int size() const { return int(states_.size()); }
  int num_consider() const { return num_consider_; }
  bool started() const { return started_; }
  double time_s() const { return time_s_; }

  // Starts (or restarts) from independent variances, one per state, at time_s.
  void reset(const Eigen::VectorXd& variances, double time_s);
  // Forgets what is known about state i: its row and column are zeroed and
  // its variance set (a state a search has just moved).
  void restart_state(int i, double variance);
  // Moves the covariance to time_s (>= time_s()).
  void predict_to(double time_s);
  // Adds process noise to state i's variance (>= 0), in the filter's and the
  // reported covariance alike: a random walk driven by something other
  // than time (camera_carrier_motion.h).
  void add_variance(int i, double variance);
  // Folds in an image's information about the states' DOFs (their angles),
  // in states() order, times `information_scale` (with consider parameters:
  // an image that says nothing about them).
  void update(const Eigen::MatrixXd& angle_information, double information_scale);
  // The same with the image's information between the DOFs' angles and the
  // consider parameters (size() x num_consider(), in their units).
  // `noise_scale` in [0, 1] scales the pixel noise's term P+ J_xx P+: the
  // noise the image's pixels put into the fit as a share of what the
  // weights assume (ImageInformation::fitted_residual_factor() times the
  // information scale; 1: the weights' own).
  void update(const Eigen::MatrixXd& angle_information, const Eigen::MatrixXd& consider_cross,
              double information_scale, double noise_scale = 1);
  // The same, where the states flagged in `widened` (one flag per state)
  // take their response to the consider parameters from `widened_cross`
  // instead (the same shape, larger columns): their error moves with the
  // parameters as if those were larger, the others' as consider_cross says.
  // Any such split is the covariance of a linear error model, so Q stays
  // positive semi-definite.
  void update(const Eigen::MatrixXd& angle_information, const Eigen::MatrixXd& consider_cross,
              const Eigen::MatrixXd& widened_cross, const std::vector<char>& widened,
              double information_scale, double noise_scale = 1);
  // Variance of state i in the reported covariance after predicting to
  // time_s (>= time_s()), without changing the covariance.
  double variance_at(int i, double time_s) const;
  // The reported covariance of the states' DOFs' angle errors (D Q_ee D, or
  // D P D without consider parameters), without encoder noise.
  Eigen::MatrixXd angle_covariance() const;
  // The same into `out` (no allocation once `out` has the size).
  void angle_covariance(Eigen::MatrixXd& out) const;
  // angle_covariance() as predict_to(time_s) would leave it (time_s >=
  // time_s()), the covariance unchanged: what the estimate reports between
  // images, without a copy of the whole filter. The same numbers to the bit.
  void angle_covariance_at(double time_s, Eigen::MatrixXd& out) const;
  // The same from the filter's own covariance P (its weights), into `out`
  // (no allocation once `out` has the size).
  void nominal_angle_covariance(Eigen::MatrixXd& out) const;
  // The reported covariance of the states (Q_ee, or P).
  Eigen::MatrixXd covariance() const;
  const Eigen::MatrixXd& nominal_covariance() const { return P_; }

 private:
  // Q_ee with consider parameters, else P: what every accessor above reports.
  const Eigen::MatrixXd& reported() const { return num_consider_ > 0 ? Q_ee_ : P_; }

  std::vector<State> states_;
  Eigen::VectorXd sign_;  // D's diagonal
  int num_consider_ = 0;
  // Every matrix an update uses is sized at construction, so an image's
  // update allocates nothing (it runs per image on the image thread).
  Eigen::MatrixXd P_, scratch_, identity_;
  Eigen::MatrixXd J_;                        // the last image's J_xx
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;  // of Id + P s D I D
  // With consider parameters: the error's covariance with them, and scratch.
  Eigen::MatrixXd Q_ee_, Q_ec_, A_, B_, AQ_, PJ_;
  Eigen::MatrixXd B_widened_;     // B from widened_cross
  Eigen::MatrixXd signed_cross_;  // D times a cross-information

  // The three update()s: a null part is absent. Checks every size.
  void update(const Eigen::MatrixXd& angle_information, const Eigen::MatrixXd* consider_cross,
              const Eigen::MatrixXd* widened_cross, const std::vector<char>* widened,
              double information_scale, double noise_scale);
  void update_nominal(const Eigen::MatrixXd& angle_information, double information_scale);
  void propagate_error(const Eigen::MatrixXd* consider_cross, double information_scale,
                       const Eigen::MatrixXd* widened_cross, const std::vector<char>* widened,
                       double noise_scale);
  double time_s_ = 0;
  bool started_ = false;
};

}  // namespace arttrack
