#include "arttrack/tracker/internal/acquisition.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "arttrack/tracker/internal/gaussian_fold.h"
#include "elapsed.h"
#include "health_check.h"

namespace arttrack {
namespace {

using Clock = std::chrono::steady_clock;

// log N(x; mean, sd^2) up to its constant: a prior's term in a search's target.
double gaussian_log_kernel(double x, double mean, double sd) {
  const double u = (x - mean) / sd;
  return -0.5 * u * u;
}

}  // namespace

AcquisitionSetup::AcquisitionSetup(const TrackerSetup& setup)
    : on(setup.config.method == TrackingMethod::kFullFusion && setup.config.acquisition.passes > 1),
      tracker(setup),
      params(setup.config.acquisition),
      reopened_bias_var_rad2(params.bias_std_rad * params.bias_std_rad) {
  if (!on) return;
  const RobotModel& model = *setup.model;
  for (int j = 0; j < setup.n_phys; ++j)
    if (setup.bias_estimated[j]) blocks.push_back({model.joint_name(j), {j}});
  for (int j = setup.n_phys; j < setup.n; ++j) blocks.push_back({model.joint_name(j), {j}});
  const DepthModelParams& pixel = setup.config.depth_model;
  const int K = params.passes;
  for (int k = 0; k + 1 < K; ++k) {
    // Depth noise from coarse to the pixel model's, geometrically.
    DepthModelParams p = pixel;
    p.noise_std_m =
        params.coarse_noise_std_m *
        std::pow(pixel.noise_std_m / params.coarse_noise_std_m, double(k) / double(K - 1));
    pass_models.push_back(p);
  }
}

AcquisitionWorkspace::AcquisitionWorkspace(const AcquisitionSetup& setup) {
  const int n = setup.tracker.n;
  part_open.assign(n, 0);
  if (!setup.on) return;
  cpf.emplace(n, setup.blocks,
              particle_filter_params(setup.tracker.config, int(setup.blocks.size())));
  for (const DepthModelParams& p : setup.pass_models) likelihoods.emplace_back(p);
  search_mean.assign(n, 0.0);
  search_std.assign(n, 0.0);
  open_mean.assign(n, 0.0);
  open_std.assign(n, 0.0);
  found_mean.assign(n, 0.0);
  found_variance.assign(n, 0.0);
  candidate.assign(n, 0.0);
}

Acquisition::Acquisition(const TrackerSetup& setup) : setup_(setup), ws_(setup_) {}

void Acquisition::draw(const RenderGeometry& geometry) {
  if (ws_.cpf)
    ws_.evaluator = std::make_unique<HypothesisEvaluator>(geometry.drawn_model(), ws_.cpf->blocks(),
                                                          HypothesisEvaluator::Mode::kCached,
                                                          geometry.render_options());
}

double Acquisition::acquire_first(ImageFilter& image, const DepthImage& observed,
                                  std::span<const double> prior_std, double time_s,
                                  JointBelief& belief, TrackingHealth& health) {
  const auto start = Clock::now();
  const int n = setup_.tracker.n, n_phys = setup_.tracker.n_phys;
  std::vector<double> first_search_std(prior_std.begin(), prior_std.end());  // once per tracker
  if (!setup_.params.search_camera)
    for (int j = n_phys; j < n; ++j) first_search_std[j] = 0;
  acquire(image, observed, belief.mean_a, first_search_std);
  if (!setup_.params.search_camera)
    for (int j = n_phys; j < n; ++j) ws_.found_variance[j] = belief.var_a[j];
  fold_angle_posteriors(ws_.found_mean, ws_.found_variance, belief);
  const double ms = health.last_acquisition_ms = ms_since(start);
  ++health.acquisitions;
  ws_.last_search_s = time_s;
  return ms;
}

SearchKind Acquisition::due_search(const HealthCheck& check, double time_s) const {
  const AcquisitionSetup& s = setup_;
  const bool periodic = s.params.period_s > 0 && time_s - ws_.last_search_s >= s.params.period_s;
  const int lost_after = s.tracker.config.health.lost_after_images;
  const int due = lost_after << std::min(check.failed_reacquisitions(), 4);
  const int due_unconfirmed = lost_after << std::min(check.failed_confirmations(), 5);
  bool confirm = false;
  for (std::size_t c = 0; c < check.chains().size(); ++c)
    confirm = confirm || check.unconfirmed_images(c) >= due_unconfirmed;
  const bool poor = check.poor_images() >= due;
  if (poor) return SearchKind::kPoor;
  if (confirm) return SearchKind::kConfirming;
  return periodic ? SearchKind::kPeriodic : SearchKind::kNone;
}

void Acquisition::search(ImageFilter& image, const DepthImage& observed,
                         std::span<const double> mean, std::span<const double> stddev) {
  AcquisitionWorkspace& w = ws_;
  const int n = setup_.tracker.n;
  std::copy(mean.begin(), mean.end(), w.search_mean.begin());
  double scale = 1;
  for (std::size_t k = 0; k < w.likelihoods.size(); ++k) {
    for (int j = 0; j < n; ++j) w.search_std[j] = scale * stddev[j];
    w.likelihoods[k].set_observation(observed);
    w.evaluator->begin_run(image.camera(), w.likelihoods[k], w.search_mean);
    w.cpf->run(mean, stddev, w.search_mean, w.search_std, image.likelihood_exponent(), *w.evaluator,
               image.rng(), image.pool());
    std::copy(w.cpf->mean().begin(), w.cpf->mean().end(), w.search_mean.begin());
    scale *= setup_.params.proposal_shrink;
  }
  for (int j = 0; j < n; ++j) w.search_std[j] = scale * stddev[j];
}

void Acquisition::acquire(ImageFilter& image, const DepthImage& observed,
                          std::span<const double> mean, std::span<const double> stddev) {
  AcquisitionWorkspace& w = ws_;
  const int n = setup_.tracker.n;
  double best_target = -std::numeric_limits<double>::infinity();
  for (int attempt = 0; attempt < setup_.params.searches; ++attempt) {
    search(image, observed, mean, stddev);
    image.run(mean, stddev, w.search_mean, w.search_std);
    const std::span<const double> found = image.filter().mean();
    double target = image.score(found);
    for (int j = 0; j < n; ++j)
      if (stddev[j] > 0) target += gaussian_log_kernel(found[j], mean[j], stddev[j]);
    // The first search always fills found_* (even if its target is NaN).
    if (!(target > best_target) && attempt > 0) continue;
    best_target = target;
    std::copy(found.begin(), found.end(), w.found_mean.begin());
    std::copy(image.filter().variance().begin(), image.filter().variance().end(),
              w.found_variance.begin());
  }
}

void Acquisition::open_weakest_parts(const HealthCheck& check, const TrackingHealth& health,
                                     const JointBelief& belief) {
  // Only each unconfirmed chain's weakest part is searched; the rest of the
  // estimate, which the image confirms, is held (a zero proposal std). A
  // search of the whole arm from the encoders finds the same wrong wrist the
  // first one did; with the arm held, the hand's few DOFs are searched with
  // every particle.
  AcquisitionWorkspace& w = ws_;
  const RobotModel& model = *setup_.tracker.model;
  std::fill(w.part_open.begin(), w.part_open.end(), 0);
  for (std::size_t c = 0; c < check.chains().size(); ++c) {
    if (check.unconfirmed_images(c) == 0) continue;
    const std::vector<int>& chain = check.chains()[c];
    for (const auto& [dof, links] : check.parts(c)) {
      if (dof != health.chains[c].weakest_part_joint) continue;
      for (int k : chain)
        if (links[std::size_t(model.joint_child_link(k))]) w.part_open[k] = 1;
      // And the joint above it: the wrong hand measured came with the two
      // wrist joints off in opposite senses (15 and 17 degrees). Each search
      // in a row that left the chain unconfirmed opens one joint more up the
      // chain: after an encoder slip of three wrist joints the part and the
      // joint above it were searched for 1.5 s with the third joint held 30
      // degrees off.
      int above = 1 + check.failed_confirmations();
      for (int l = model.link(model.joint_child_link(dof)).parent; l >= 0 && above > 0;
           l = model.link(l).parent) {
        const int up = model.link(l).dof;
        if (up < 0 || model.is_virtual_joint(up)) continue;
        if (std::find(chain.begin(), chain.end(), up) == chain.end()) break;
        w.part_open[up] = 1;
        --above;
      }
    }
  }
  for (int j = 0; j < setup_.tracker.n; ++j) {
    if (w.part_open[j]) continue;
    w.open_mean[j] = belief.mean_a[j];
    w.open_std[j] = 0;
  }
}

void Acquisition::reacquire(SearchKind kind, ImageFilter& image, const DepthImage& observed,
                            HealthCheck& check, std::span<const double> reading, double time_s,
                            JointBelief& belief, TrackingHealth& health,
                            std::vector<char>& reopened) {
  const auto start = Clock::now();
  AcquisitionWorkspace& w = ws_;
  const TrackerSetup& t = setup_.tracker;
  const bool periodic = kind == SearchKind::kPeriodic;
  const double var_b = setup_.reopened_bias_var_rad2;
  const auto var_q = t.filter_model->encoder_var_rad2();
  for (int j = 0; j < t.n; ++j) {
    const bool open = j < t.n_phys && t.bias_estimated[j];
    w.open_mean[j] = open ? reading[j] : belief.mean_a[j];
    w.open_std[j] = std::sqrt(open ? var_b + var_q[j] : std::max(0.0, belief.var_a[j]));
  }
  if (kind == SearchKind::kConfirming) open_weakest_parts(check, health, belief);
  auto log_prior = [&](int j, double a) {
    return gaussian_log_kernel(a, w.open_mean[j], w.open_std[j]);
  };
  acquire(image, observed, w.open_mean, w.open_std);
  const std::vector<double>& found = w.found_mean;
  const std::vector<double>& found_var = w.found_variance;
  std::copy(belief.mean_a.begin(), belief.mean_a.end(), w.candidate.begin());
  double current_score = image.score(w.candidate);
  for (std::size_t c = 0; c < check.chains().size(); ++c) {
    const std::vector<int>& chain = check.chains()[c];
    // Triggered by the health check, only the chains it found poor may
    // change: a chain out of view (no verdict) keeps what the encoders say,
    // rather than a search placing it over some other surface.
    const bool unconfirmed = check.unconfirmed_images(c) > 0;
    if (!periodic && !check.chain_poor(c) && !unconfirmed) continue;
    double gain = 0;
    bool differs = false;
    for (int j : chain) {
      if (!t.bias_estimated[j] || !(w.open_std[j] > 0)) continue;
      gain += log_prior(j, found[j]) - log_prior(j, belief.mean_a[j]);
      w.candidate[j] = found[j];
      differs = true;
    }
    if (!differs) continue;
    const double candidate_score = image.score(w.candidate);
    gain += candidate_score - current_score;
    // A chain that nothing contradicts (only unconfirmed: part of it
    // unexplained, as behind a panel close in front of it) takes only a
    // result that the image confirms, or explains better than the estimate.
    // Else the search trades the arm's visible pixels for another surface
    // (the panel's) or hides it behind the occluder, and the arm leaves
    // where the encoders and its learned biases put it. (Checked only for a
    // result the image prefers.)
    if (gain > setup_.params.accept_margin_nats &&
        (check.chain_poor(c) || periodic ||
         check.supports_chain(w.candidate, c, observed, image.geometry().renderer(),
                              health.chains[c].weakest_part_explained_fraction))) {
      current_score = candidate_score;  // the next chain is compared with this one taken
      for (int j : chain) {
        if (!t.bias_estimated[j] || !(w.open_std[j] > 0)) continue;
        const AngleBiasGaussian reopened_prior{reading[j], 0.0, var_b + var_q[j], -var_b, var_b};
        belief.set_joint(j, fold_angle_marginal(reopened_prior, found[j], found_var[j]));
        reopened[j] = 1;
      }
      ++health.chains_reacquired;
    } else {
      for (int j : chain) w.candidate[j] = belief.mean_a[j];
    }
  }
  ++health.acquisitions;
  health.last_acquisition_ms = ms_since(start);
  w.last_search_s = time_s;
  if (kind == SearchKind::kConfirming) {
    check.confirming_search_ran();
    return;
  }
  check.reacquisition_ran();
}

}  // namespace arttrack
