#include "arttrack/tracker/internal/refinement.h"

#include "arttrack/tracker/internal/gaussian_fold.h"

namespace arttrack {
namespace {

// Per state: the encoders' noise variance for a bias state, else 0.
Eigen::VectorXd encoder_var_per_state(const TrackerSetup& setup,
                                      const std::vector<PosteriorCovariance::State>& states) {
  Eigen::VectorXd var_q = Eigen::VectorXd::Zero(Eigen::Index(states.size()));
  for (std::size_t i = 0; i < states.size(); ++i)
    if (states[i].kind == PosteriorCovariance::Kind::kBias)
      var_q[Eigen::Index(i)] = setup.filter_model->encoder_var_rad2()[states[i].dof];
  return var_q;
}

}  // namespace

Refinement::Refinement(const TrackerSetup& setup,
                       const std::vector<PosteriorCovariance::State>& states)
    : on_(setup.config.method == TrackingMethod::kFullFusion && setup.config.refine_mean),
      widen_beyond_sigma_(setup.config.refinement_widen_beyond_sigma),
      solver_(encoder_var_per_state(setup, states), setup.config.refinement_min_pixels,
              setup.config.likelihood_exponent, setup.config.refinement_unseen_information_ratio),
      x_(Eigen::Index(states.size())),
      spread_(states.size()),
      q_(std::size_t(setup.n)) {}

bool Refinement::refine(const PosteriorCovariance& covariance, const ImageInformation& information,
                        std::span<const double> prior_mean, std::span<const double> prior_std,
                        ImageFilter& image, JointBelief& belief) {
  const auto& states = covariance.states();
  const int m = covariance.size();
  const int n = int(q_.size());
  for (int i = 0; i < m; ++i) {
    const int dof = states[std::size_t(i)].dof;
    x_[i] = belief.mean_a[dof] - prior_mean[dof];  // theta - mu
    spread_[std::size_t(i)] = prior_std[dof];
  }
  covariance.nominal_angle_covariance(nominal_);
  if (!solver_.solve(nominal_, x_, information.information_matrix(), information.gradient(),
                     information.motion_field_information(), information.pixels_per_dof(), spread_))
    return false;
  if (widen_beyond_sigma_ > 0) {
    covariance.angle_covariance(reported_);
    solver_.widen(reported_, widen_beyond_sigma_, spread_);
  }
  const Eigen::VectorXd& step = solver_.step();
  auto target = [&](double fraction) {
    for (int j = 0; j < n; ++j) q_[std::size_t(j)] = belief.mean_a[j];
    for (int i = 0; i < m; ++i) q_[std::size_t(states[std::size_t(i)].dof)] += fraction * step[i];
    return solver_.log_prior(fraction) + image.score(q_);
  };
  const double current = target(0);
  double best = current, best_fraction = 0;
  for (double fraction : {1.0, 0.5}) {
    const double value = target(fraction);
    if (value > best) {
      best = value;
      best_fraction = fraction;
    }
  }
  if (best_fraction == 0) return false;
  for (int i = 0; i < m; ++i) {
    const int dof = states[std::size_t(i)].dof;
    belief.set_joint(
        dof, fold_angle_marginal(belief.joint(dof), belief.mean_a[dof] + best_fraction * step[i],
                                 belief.var_a[dof]));
  }
  return true;
}

}  // namespace arttrack
