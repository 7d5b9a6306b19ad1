// The per-joint 2-D Gaussian belief over (angle, encoder bias) and the fold-back
// of an image's angle posterior into it (paper Sec. "Full posterior", Eqs. (12)
// and (17); docs/method.md "Fold-back into the joint filters").
//
// After an image, the particle filter gives a new Gaussian over the angle a
// only. The image says nothing about the bias b directly (Eq. (11)), so the
// posterior is p(a | image) p(b | a): the new angle Gaussian combined with the
// prior's conditional p(b | a), which Gaussian conditioning gives in closed
// form. The result is again a 2-D Gaussian, so the joint Kalman filter goes on
// unchanged, and this is how biases are learned from images.
#pragma once

namespace arttrack {

// A Gaussian over (angle a, bias b) of one joint: radians (metres for a
// prismatic virtual joint). A joint without bias has mean_b = var_b = cov_ab = 0.
struct AngleBiasGaussian {
  double mean_a = 0;
  double mean_b = 0;
  double var_a = 0;
  double cov_ab = 0;
  double var_b = 0;
};

// The conditional p(b | a) = N(b; intercept + slope * a, residual_var) of a
// 2-D Gaussian. A degenerate angle variance (var_a <= 0) gives slope 0: b is
// then independent of a as far as the belief can tell.
struct BiasGivenAngle {
  double slope = 0;         // cov_ab / var_a
  double intercept = 0;     // mean_b - slope * mean_a
  double residual_var = 0;  // var_b - cov_ab^2 / var_a, clamped at 0
};

BiasGivenAngle bias_given_angle(const AngleBiasGaussian& g);

// p(a) := N(new_mean_a, new_var_a) times the prior's p(b | a):
//   mean_a = new_mean_a, var_a = new_var_a,
//   mean_b = m_b + k (new_mean_a - m_a),  cov_ab = k new_var_a,
//   var_b  = (P_bb - k P_ab) + k^2 new_var_a,  with k = P_ab / P_aa.
// The conditional p(b | a) of the result equals the prior's.
AngleBiasGaussian fold_angle_marginal(const AngleBiasGaussian& prior, double new_mean_a,
                                      double new_var_a);

}  // namespace arttrack
