#include "mean_refinement.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace arttrack {

MeanRefinement::MeanRefinement(Eigen::VectorXd encoder_var_rad2, int min_pixels,
                               double likelihood_exponent)
    : encoder_var_rad2_(std::move(encoder_var_rad2)),
      min_pixels_(min_pixels),
      beta_(likelihood_exponent) {}

bool MeanRefinement::solve(const Eigen::MatrixXd& nominal_covariance, const Eigen::VectorXd& x,
                           const Eigen::MatrixXd& information, const Eigen::VectorXd& gradient,
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
  rhs_ = beta_ * gradient - system_ * x_;
  system_ += beta_ * information;
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
  delta_ = system_.partialPivLu().solve(rhs_);
  if (!delta_.allFinite()) return false;
  // Trust region: no state moves further than the particles' own spread;
  // a longer step is shortened along its direction. A step beyond where the
  // particles looked is a linearisation far from its point, and could cross
  // into another mode.
  double longest = 0;
  for (Eigen::Index i = 0; i < m; ++i)
    if (delta_[i] != 0) longest = std::max(longest, std::abs(delta_[i]) / spread[std::size_t(i)]);
  if (!std::isfinite(longest)) return false;
  if (longest > 1) delta_ /= longest;
  return true;
}

double MeanRefinement::log_prior(double fraction) const {
  const Eigen::VectorXd d = x_ + fraction * delta_;
  return -0.5 * d.dot(prior_ldlt_.solve(d));
}

}  // namespace arttrack
