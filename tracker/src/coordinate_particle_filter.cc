#include "arttrack/tracker/internal/coordinate_particle_filter.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/worker_pool.h"
#include "config_range.h"

namespace arttrack {

// ------------------------------------------------------------- evaluators

void PerParticleEvaluator::evaluate(const ParticleBatch& batch, std::span<double> log_likelihood,
                                    WorkerPool& pool) {
  pool.parallel_for(batch.num_particles, [&](int begin, int end, int worker) {
    for (int l = begin; l < end; ++l) log_likelihood[l] = this->log_likelihood(batch, l, worker);
  });
}

double kl_divergence_from_uniform(std::span<const double> weights) {
  const double n = double(weights.size());
  double kl = 0;
  for (double w : weights) {
    if (w > 0) kl += w * std::log(n * w);
  }
  return std::max(0.0, kl);  // >= 0 exactly; rounding may dip below
}

// ------------------------------------------------------------------- filter

void CoordinateParticleFilterParams::validate(std::string_view source,
                                              const std::string& prefix) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  check_range(source, prefix + "particles", num_particles, ConfigRange::closed(1, 1e6));
  check_range(source, prefix + "max_kl_divergence", max_kl_divergence,
              ConfigRange::closed(0, kInf));
  check_range(source, prefix + "proposal_scale", proposal_scale, ConfigRange::closed(1e-6, 1e6));
  check_range(source, prefix + "no_evidence_nats", no_evidence_nats, ConfigRange::closed(0, kInf));
  check_range(source, prefix + "bandwidth_factor", bandwidth_factor, ConfigRange::closed(0, 10));
  check_range(source, prefix + "block_moments_below_nats", block_moments_below_nats,
              ConfigRange::closed(0, kInf));
}

CoordinateParticleFilter::CoordinateParticleFilter(int dimension, std::vector<SamplingBlock> blocks,
                                                   const CoordinateParticleFilterParams& params)
    : dimension_(dimension), blocks_(std::move(blocks)), params_(params) {
  if (dimension_ <= 0) throw InputError("particle filter: dimension must be positive");
  params_.validate("particle filter");
  if (blocks_.empty()) throw InputError("particle filter: no sampling blocks");
  sampled_.assign(dimension_, false);
  for (const SamplingBlock& b : blocks_) {
    if (b.coordinates.empty()) {
      throw InputError("particle filter: sampling block '" + b.name + "' is empty");
    }
    for (int c : b.coordinates) {
      if (c < 0 || c >= dimension_) {
        throw InputError("particle filter: sampling block '" + b.name + "': coordinate " +
                         std::to_string(c) + " outside [0, " + std::to_string(dimension_) + ")");
      }
      if (sampled_[c]) {
        throw InputError("particle filter: sampling block '" + b.name + "': coordinate " +
                         std::to_string(c) + " is already in another block");
      }
      sampled_[c] = true;
    }
  }
  num_particles_ = params_.num_particles;
  const std::size_t ln = std::size_t(num_particles_) * dimension_;
  particles_.resize(ln);
  scratch_particles_.resize(ln);
  log_weights_.resize(num_particles_);
  weights_.resize(num_particles_);
  log_likelihood_.resize(num_particles_);
  new_log_likelihood_.resize(num_particles_);
  scratch_log_likelihood_.resize(num_particles_);
  correction_.resize(num_particles_);
  parents_.resize(num_particles_);
  mean_.resize(dimension_);
  variance_.resize(dimension_);
  informed_.resize(dimension_);
  matched_.resize(dimension_);
}

void CoordinateParticleFilter::normalise_weights() {
  const double max_log_w = *std::max_element(log_weights_.begin(), log_weights_.end());
  double sum = 0;
  for (int l = 0; l < num_particles_; ++l) {
    weights_[l] = std::exp(log_weights_[l] - max_log_w);
    sum += weights_[l];
  }
  for (double& w : weights_) w /= sum;
}

// Systematic resampling: one uniform offset u in [0, 1/L), then particle l
// copies the particle whose cumulative-weight interval contains u + l / L.
void CoordinateParticleFilter::resample(std::mt19937_64& rng) {
  const int L = num_particles_;
  const double u0 = std::uniform_real_distribution<double>(0.0, 1.0)(rng) / L;
  double cumulative = weights_[0];
  int source = 0;
  for (int l = 0; l < L; ++l) {
    const double u = u0 + double(l) / L;
    while (u > cumulative && source < L - 1) cumulative += weights_[++source];
    parents_[l] = source;
  }
  for (int l = 0; l < L; ++l) {
    const double* from = particles_.data() + std::size_t(parents_[l]) * dimension_;
    std::copy(from, from + dimension_, scratch_particles_.data() + std::size_t(l) * dimension_);
    scratch_log_likelihood_[l] = log_likelihood_[parents_[l]];
  }
  particles_.swap(scratch_particles_);
  log_likelihood_.swap(scratch_log_likelihood_);
  std::fill(log_weights_.begin(), log_weights_.end(), 0.0);
  std::fill(weights_.begin(), weights_.end(), 1.0 / L);
  ++num_resamplings_;
}

void CoordinateParticleFilter::run(std::span<const double> prior_mean,
                                   std::span<const double> prior_std,
                                   LogLikelihoodEvaluator& evaluator, std::mt19937_64& rng,
                                   WorkerPool& pool) {
  run(prior_mean, prior_std, prior_mean, prior_std, 1.0, evaluator, rng, pool);
}

void CoordinateParticleFilter::run(std::span<const double> prior_mean,
                                   std::span<const double> prior_std,
                                   std::span<const double> proposal_mean,
                                   std::span<const double> proposal_std, double likelihood_exponent,
                                   LogLikelihoodEvaluator& evaluator, std::mt19937_64& rng,
                                   WorkerPool& pool) {
  const auto n_size = std::size_t(dimension_);
  if (prior_mean.size() != n_size || prior_std.size() != n_size || proposal_mean.size() != n_size ||
      proposal_std.size() != n_size)
    throw InputError("particle filter: prior and proposal must have " + std::to_string(dimension_) +
                     " coordinates");
  if (!(likelihood_exponent > 0 && likelihood_exponent <= 1))
    throw InputError("particle filter: likelihood_exponent = " +
                     std::to_string(likelihood_exponent) + " must be in (0, 1]");
  const int L = num_particles_;
  const int n = dimension_;
  const double beta = likelihood_exponent;
  // Proposal = prior (the plain CPF): no correction, the same numbers as ever.
  const bool corrected =
      proposal_mean.data() != prior_mean.data() || proposal_std.data() != prior_std.data();
  for (int l = 0; l < L; ++l) {
    std::copy(proposal_mean.begin(), proposal_mean.end(), particles_.begin() + std::size_t(l) * n);
  }
  std::fill(log_weights_.begin(), log_weights_.end(), 0.0);
  std::fill(weights_.begin(), weights_.end(), 1.0 / L);
  // Every particle starts at the mean: a common log-likelihood, taken as 0.
  std::fill(log_likelihood_.begin(), log_likelihood_.end(), 0.0);
  std::iota(parents_.begin(), parents_.end(), 0);
  num_evaluations_ = num_resamplings_ = num_degenerate_ = 0;
  std::fill(informed_.begin(), informed_.end(), 0);
  std::normal_distribution<double> normal(0.0, 1.0);  // fresh: no cached draw from a past run

  for (int step = 0; step < int(blocks_.size()); ++step) {
    const SamplingBlock& block = blocks_[step];
    if (step > 0 && kl_divergence_from_uniform(weights_) > params_.max_kl_divergence) {
      resample(rng);
    }
    // Draw the block from its (scaled) prior marginal, particle by particle
    // in a fixed order so the numbers depend on the seed only.
    // With a proposal other than the prior, each draw also carries
    // log prior(x) - log proposal(x) (correction_).
    for (int l = 0; l < L; ++l) {
      double* x = particles_.data() + std::size_t(l) * n;
      double correction = 0;
      for (int c : block.coordinates) {
        const double s_q = params_.proposal_scale * proposal_std[c];
        const double eps = normal(rng);
        x[c] = proposal_mean[c] + s_q * eps;
        if (corrected) {
          const double s_p = params_.proposal_scale * prior_std[c];
          if (s_p > 0 && s_q > 0) {
            const double u = (x[c] - prior_mean[c]) / s_p;
            correction += -0.5 * u * u - std::log(s_p) + 0.5 * eps * eps + std::log(s_q);
          }
        }
      }
      correction_[l] = correction;
    }
    ParticleBatch batch;
    batch.block = step;
    batch.coordinates = block.coordinates;
    batch.particles = particles_.data();
    batch.num_particles = L;
    batch.dimension = n;
    batch.parents = parents_;
    evaluator.evaluate(batch, new_log_likelihood_, pool);
    // A block held at its mean (proposal spread 0) draws nothing new.
    if (std::any_of(block.coordinates.begin(), block.coordinates.end(),
                    [&](int c) { return proposal_std[c] > 0; }))
      num_evaluations_ += L;

    // Weight by the likelihood ratio: log w += log p(I | x new) - log p(I | x old).
    // An impossible particle stays impossible. The spread of the ratios over
    // the particles that were possible tells whether the block saw evidence.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double lowest_ratio = kInf, highest_ratio = -kInf;
    for (int l = 0; l < L; ++l) {
      double ll = beta * new_log_likelihood_[l];
      if (!std::isfinite(ll)) ll = -kInf;
      if (std::isfinite(log_likelihood_[l]) && std::isfinite(log_weights_[l])) {
        const double ratio = ll - log_likelihood_[l];
        log_weights_[l] += ratio + correction_[l];
        lowest_ratio = std::min(lowest_ratio, ratio);
        highest_ratio = std::max(highest_ratio, ratio);
      } else {
        log_weights_[l] = -kInf;
      }
      log_likelihood_[l] = ll;
    }
    const double ratio_spread = highest_ratio - lowest_ratio;  // NaN or -inf: no possible particle
    bool evidence = ratio_spread > params_.no_evidence_nats;
    if (!std::isfinite(*std::max_element(log_weights_.begin(), log_weights_.end()))) {
      // No particle explains the image at all: keep the particles, ignore
      // this block's evidence. Log-likelihoods restart at a common 0.
      std::fill(log_weights_.begin(), log_weights_.end(), 0.0);
      std::fill(log_likelihood_.begin(), log_likelihood_.end(), 0.0);
      ++num_degenerate_;
      evidence = false;
    }
    if (evidence) {
      for (int c : block.coordinates) informed_[c] = 1;
    }
    normalise_weights();
    std::iota(parents_.begin(), parents_.end(), 0);
    // A block the image informed only weakly is matched now, before the
    // later blocks' resampling picks a few of its draws at random.
    const bool match_now = ratio_spread >= 0 && ratio_spread < params_.block_moments_below_nats;
    for (int c : block.coordinates) {
      matched_[c] = match_now;
      if (match_now) moment_match(c);
    }
  }

  // Every other coordinate (in no block, or in a block not matched above)
  // is matched with the final weights.
  for (int c = 0; c < n; ++c) {
    if (!matched_[c]) moment_match(c);
  }
  const double bandwidth = params_.bandwidth_factor * std::pow(double(L), -0.2);
  for (int c = 0; c < n; ++c) {
    // Never above the prior: an image must not add uncertainty (a floor
    // above it lets the virtual joints' variance grow without bound).
    const double h = std::min(bandwidth * params_.proposal_scale * proposal_std[c], prior_std[c]);
    variance_[c] = std::max(variance_[c], h * h);
    if (!informed_[c]) {  // in no block, or its block saw no evidence
      mean_[c] = prior_mean[c];
      variance_[c] = prior_std[c] * prior_std[c];
    }
  }
  // The log-likelihood (tempered) of the heaviest particle, for health checks.
  best_log_likelihood_ = -std::numeric_limits<double>::infinity();
  double best_w = -1;
  for (int l = 0; l < L; ++l)
    if (weights_[l] > best_w) best_w = weights_[l], best_log_likelihood_ = log_likelihood_[l];
}

void CoordinateParticleFilter::moment_match(int c) {
  const int n = dimension_;
  double mean = 0, variance = 0;
  for (int l = 0; l < num_particles_; ++l) mean += weights_[l] * particles_[std::size_t(l) * n + c];
  for (int l = 0; l < num_particles_; ++l) {
    const double d = particles_[std::size_t(l) * n + c] - mean;
    variance += weights_[l] * d * d;
  }
  mean_[c] = mean;
  variance_[c] = variance;
}

double CoordinateParticleFilter::effective_sample_size() const {
  double sum_sq = 0;
  for (double w : weights_) sum_sq += w * w;
  return 1 / sum_sq;
}

}  // namespace arttrack
