#include "arttrack/tracker/internal/gaussian_fold.h"

#include <algorithm>

namespace arttrack {

BiasGivenAngle bias_given_angle(const AngleBiasGaussian& g) {
  BiasGivenAngle c;
  if (g.var_a > 0) {
    c.slope = g.cov_ab / g.var_a;
    // P_bb - P_ab^2 / P_aa is the Schur complement; rounding can make it a
    // hair negative when the pair is (nearly) perfectly correlated.
    c.residual_var = std::max(0.0, g.var_b - c.slope * g.cov_ab);
  } else {
    c.residual_var = g.var_b;
  }
  c.intercept = g.mean_b - c.slope * g.mean_a;
  return c;
}

AngleBiasGaussian fold_angle_marginal(const AngleBiasGaussian& prior, double new_mean_a,
                                      double new_var_a) {
  const BiasGivenAngle c = bias_given_angle(prior);
  AngleBiasGaussian out;
  out.mean_a = new_mean_a;
  out.var_a = new_var_a;
  // b = m_b + slope (a - m_a) + e, e ~ N(0, residual_var) independent of a.
  out.mean_b = prior.mean_b + c.slope * (new_mean_a - prior.mean_a);
  out.cov_ab = c.slope * new_var_a;
  out.var_b = c.residual_var + c.slope * c.slope * new_var_a;
  return out;
}

}  // namespace arttrack
