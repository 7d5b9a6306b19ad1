#include "mean_refinement.h"

#include <algorithm>
#include <cmath>

namespace arttrack {

MeanRefinement::MeanRefinement(Eigen::VectorXd encoder_var_rad2, int min_pixels,
                               double likelihood_exponent, double unseen_ratio)
    : encoder_var_rad2_(std::move(encoder_var_rad2)),
      min_pixels_(min_pixels),
      beta_(likelihood_exponent),
      unseen_ratio_(unseen_ratio) {}

bool MeanRefinement::solve(const Eigen::MatrixXd& nominal_covariance, const Eigen::VectorXd& x,
                           const Eigen::MatrixXd& information, const Eigen::VectorXd& gradient,
                           const Eigen::MatrixXd& field_information,
                           const std::vector<int>& pixels_per_state,
                           std::span<const double> spread) {
  const Eigen::Index m = x.size();
  prior_ = nominal_covariance;
  prior_.diagonal() += encoder_var_rad2_;
  x_ = x;
  // Only states that enough explained pixels depend on move; the others (an
  // arm out of view, with a few pixels that happen to match the table) keep
  // the particles' mean: a broad prior would let those few pixels drag them.
  // The step is the MAP over the moving ones with the others held.
  prior_ldlt_.compute(prior_);
  system_ = prior_ldlt_.solve(Eigen::MatrixXd::Identity(m, m));  // P^-1
  unseen_directions_ =
      unseen_ratio_ > 0 ? project_out_unseen(information, gradient, field_information) : 0;
  const Eigen::MatrixXd& seen_information = unseen_directions_ ? seen_information_ : information;
  const Eigen::VectorXd& seen_gradient = unseen_directions_ ? seen_gradient_ : gradient;
  // noalias: Eigen otherwise assumes `a - B x` aliases and evaluates it into
  // a temporary (the same operations: rhs_ = a, then rhs_ -= B x).
  rhs_.noalias() = beta_ * seen_gradient - system_ * x_;
  system_ += beta_ * seen_information;
  int moving = 0;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (pixels_per_state[std::size_t(i)] >= min_pixels_) {
      ++moving;
      continue;
    }
    system_.row(i).setZero();
    system_.col(i).setZero();
    system_(i, i) = 1;
    rhs_[i] = 0;
  }
  if (moving == 0) return false;
  system_lu_.compute(system_);
  unclipped_ = system_lu_.solve(rhs_);
  if (!unclipped_.allFinite()) return false;
  // Trust region: no state moves further than the particles' own spread;
  // a longer step is shortened along its direction. A step beyond where the
  // particles looked is a linearisation far from its point, and could cross
  // into another mode.
  return shorten(spread);
}

int MeanRefinement::project_out_unseen(const Eigen::MatrixXd& information,
                                       const Eigen::VectorXd& gradient,
                                       const Eigen::MatrixXd& field_information) {
  const Eigen::Index m = prior_.rows();
  prior_llt_.compute(prior_);
  if (prior_llt_.info() != Eigen::Success) return 0;
  factor_ = prior_llt_.matrixL();
  factor_inverse_.setIdentity(m, m);
  prior_llt_.matrixL().solveInPlace(factor_inverse_);
  product_.noalias() = field_information * factor_;
  whitened_.noalias() = factor_.transpose() * product_;  // L^T F L
  tridiagonal_.compute(whitened_);
  diagonal_ = tridiagonal_.diagonal();
  subdiagonal_ = tridiagonal_.subDiagonal();
  tridiagonal_eigen_.computeFromTridiagonal(diagonal_, subdiagonal_, Eigen::ComputeEigenvectors);
  if (tridiagonal_eigen_.info() != Eigen::Success) return 0;
  // Q into a kept matrix with a kept workspace (the expression's assignment
  // makes a workspace of its own).
  tridiagonal_.matrixQ().evalTo(rotation_, householder_workspace_);
  eigenvectors_.noalias() = rotation_ * tridiagonal_eigen_.eigenvectors();
  // Eigenvalues ascend: the candidates, below unseen_ratio of the prior's
  // information (1 when whitened), come first. Each is unseen where it is
  // also below unseen_ratio of the central differences' information along
  // it, in the same units: u^T L^T I L u. The others' columns are zeroed.
  Eigen::Index candidates = 0;
  while (candidates < m && tridiagonal_eigen_.eigenvalues()[candidates] < unseen_ratio_)
    ++candidates;
  if (candidates == 0) return 0;
  product_.noalias() = information * factor_;
  whitened_.noalias() = factor_.transpose() * product_;  // L^T I L
  int unseen = 0;
  for (Eigen::Index k = 0; k < candidates; ++k) {
    column_.noalias() = whitened_ * eigenvectors_.col(k);
    const double central = eigenvectors_.col(k).dot(column_);
    if (tridiagonal_eigen_.eigenvalues()[k] < unseen_ratio_ * central)
      ++unseen;
    else
      eigenvectors_.col(k).setZero();
  }
  eigenvectors_.rightCols(m - candidates).setZero();
  if (unseen == 0) return 0;
  whitened_.setIdentity(m, m);
  whitened_.noalias() -= eigenvectors_ * eigenvectors_.transpose();  // 1 - U U^T
  product_.noalias() = whitened_ * factor_inverse_;
  projector_.noalias() = factor_ * product_;  // Pi = L (1 - U U^T) L^-1
  product_.noalias() = information * projector_;
  seen_information_.noalias() = projector_.transpose() * product_;
  seen_gradient_.noalias() = projector_.transpose() * gradient;
  return unseen;
}

bool MeanRefinement::shorten(std::span<const double> limit) {
  double longest = 0;
  for (Eigen::Index i = 0; i < unclipped_.size(); ++i)
    if (unclipped_[i] != 0)
      longest = std::max(longest, std::abs(unclipped_[i]) / limit[std::size_t(i)]);
  if (!std::isfinite(longest)) return false;
  delta_ = unclipped_;
  if (longest > 1) delta_ /= longest;
  return true;
}

bool MeanRefinement::widen(const Eigen::MatrixXd& reported_covariance, double beyond_sigma,
                           std::span<const double> spread) {
  if (!(beyond_sigma > 0)) return false;
  reported_ldlt_.compute(reported_covariance);
  if (reported_ldlt_.info() != Eigen::Success) return false;
  scratch_ = reported_ldlt_.solve(unclipped_);
  const double length2 = unclipped_.dot(scratch_);
  if (!(length2 > beyond_sigma * beyond_sigma)) return false;  // short, or not finite
  // The limits in scratch_: the larger of the spread and the reported sd.
  for (Eigen::Index i = 0; i < unclipped_.size(); ++i)
    scratch_[i] =
        std::max(spread[std::size_t(i)], std::sqrt(std::max(0.0, reported_covariance(i, i))));
  return shorten({scratch_.data(), std::size_t(scratch_.size())});
}

double MeanRefinement::log_prior(double fraction) const {
  point_ = x_ + fraction * delta_;
  point_solved_ = prior_ldlt_.solve(point_);
  return -0.5 * point_.dot(point_solved_);
}

}  // namespace arttrack
