// One Gauss-Newton step on the particle filter's target, prior x
// likelihood^beta, linearised at its mean (DART's local refinement on the
// depth residuals, with the full prior covariance; docs/accuracy.md, "The
// failure, and what the tracker does about it", item 5): the coordinate-wise
// particles cannot move along a narrow diagonal ridge (the camera turning
// while every arm turns back), and were seen to lag along it by a degree
// while the image's gradient pointed at the truth. With theta the mean, mu
// the prior's, P its angle covariance, I and g the image's information and
// gradient (image_information.h):
//   delta = (P^-1 + beta I)^-1 (beta g - P^-1 (theta - mu)),
// over the states at least min_pixels explained pixels depend on (the
// others held), I and g without their part along the directions the image
// does not see (below), shortened so that no state moves further than its
// spread (the particles' prior standard deviation), or, when the step is longer
// than widen_beyond_sigma reported standard deviations, than the larger of
// that spread and its reported standard deviation (widen()). The tracker then takes the
// full step or its half when it raises the target with the exact pixel
// model (occlusion, outliers and edges included); otherwise the mean stays.
//
// The directions the image does not see: with unseen_ratio > 0, the
// eigenvectors u of L^T F L (P = L L^T, F the motion field's information,
// surface normals: what moving a surface shows) whose eigenvalue is below
// unseen_ratio both of the prior's information along u (1, whitened) and of
// u^T L^T I L u, the central differences' information along u: the image
// says next to nothing there, and the central differences claim it says
// far more. Either test alone missed (docs/accuracy.md, stop 97): below a
// fraction of the prior's only, a small image's real, weak information
// per image falls under it once many images have narrowed the prior, and
// a planar arm's camera stayed 6 sigma off; below a fraction of the
// central differences' only, a direction the field sees at several times
// the prior's information, where a mesh's central differences read a
// hundred times more, was taken out, and the sculpted dual arm's camera
// converged over 30 s instead of 2. With Pi = L (1 - U U^T) L^-1 the
// projection onto the rest along them, I and g become Pi^T I Pi and Pi^T
// g: along an unseen direction the step is the prior's alone. Such a
// direction moves no surface (a camera orbiting an axisymmetric base link
// while the joint that turns it turns back), but I and g, from central
// differences one DOF at a time, count the edges each DOF's step moves
// across pixel centres as slopes, on different pixels per DOF, so that
// their jumps do not cancel along it: they read information there, and the
// mean walked along it (docs/accuracy.md, "Directions that move no
// surface").
//
// States are PosteriorCovariance's (posterior_covariance.h), in its order.
// Internal to the tracker (not installed). solve() allocates only when the
// number of states changes.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace arttrack {

class MeanRefinement {
 public:
  // encoder_var_rad2: per state, the encoder variance added to the prior's
  // diagonal (bias states: the encoders' noise), else 0. likelihood_exponent
  // is beta.
  // unseen_ratio: above, 0 for none.
  MeanRefinement(Eigen::VectorXd encoder_var_rad2, int min_pixels, double likelihood_exponent,
                 double unseen_ratio = 0);

  // The step from x = theta - mu under the nominal angle covariance P (the
  // filter's own weights), the image's information and gradient, the
  // motion field's information (read with unseen_ratio > 0), the explained
  // pixels per state and each state's spread. False when no state moves or
  // the step is not finite.
  bool solve(const Eigen::MatrixXd& nominal_covariance, const Eigen::VectorXd& x,
             const Eigen::MatrixXd& information, const Eigen::VectorXd& gradient,
             const Eigen::MatrixXd& field_information, const std::vector<int>& pixels_per_state,
             std::span<const double> spread);

  // After solve(): how many directions it found unseen (0 with
  // unseen_ratio 0).
  int unseen_directions() const { return unseen_directions_; }

  // After solve(): when the step before shortening is longer than
  // beyond_sigma standard deviations under `reported_covariance` (its
  // Mahalanobis length; the states' reported covariance), shortens it
  // instead so that no state moves further than the larger of its spread
  // and its reported standard deviation. The particles' spread collapses
  // within an image or two, so while the mean is still far from the image's
  // optimum it would otherwise crawl. Returns whether it widened.
  bool widen(const Eigen::MatrixXd& reported_covariance, double beyond_sigma,
             std::span<const double> spread);

  // After solve(): the step, and the log prior (up to a constant) of
  // x + fraction * step.
  const Eigen::VectorXd& step() const { return delta_; }
  double log_prior(double fraction) const;

 private:
  Eigen::VectorXd encoder_var_rad2_;
  int min_pixels_;
  double beta_;
  double unseen_ratio_;
  int unseen_directions_ = 0;
  Eigen::VectorXd x_, delta_, rhs_, unclipped_, scratch_;
  Eigen::MatrixXd prior_, system_;
  // The unseen directions' workspace: L, L^-1, L^T F L and then Pi, the
  // projected information and gradient.
  // The eigenvectors come from a tridiagonal form (Q^T L^T F L Q = T) and
  // T's eigenvectors: SelfAdjointEigenSolver::compute() allocates Q's
  // workspace on every call.
  Eigen::LLT<Eigen::MatrixXd> prior_llt_;
  Eigen::Tridiagonalization<Eigen::MatrixXd> tridiagonal_;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tridiagonal_eigen_;
  Eigen::MatrixXd factor_, factor_inverse_, whitened_, rotation_, eigenvectors_, projector_,
      product_, seen_information_;
  Eigen::VectorXd diagonal_, subdiagonal_, householder_workspace_, column_, seen_gradient_;
  Eigen::LDLT<Eigen::MatrixXd> prior_ldlt_, reported_ldlt_;
  // Kept between images (a temporary factor or vector per call allocated):
  // the step's factor, and log_prior()'s point and its solve.
  Eigen::PartialPivLU<Eigen::MatrixXd> system_lu_;
  mutable Eigen::VectorXd point_, point_solved_;

  // delta_ = unclipped_, shortened so that |delta_i| <= limit_i (0: held).
  // False when a limit is not finite.
  bool shorten(std::span<const double> limit);
  // Sets seen_information_ and seen_gradient_ (above); returns how many
  // directions are unseen.
  int project_out_unseen(const Eigen::MatrixXd& information, const Eigen::VectorXd& gradient,
                         const Eigen::MatrixXd& field_information);
};

}  // namespace arttrack
