// The Coordinate Particle Filter (Wüthrich, Bohg, Kappler, Pfreundt, Schaal,
// "The Coordinate Particle Filter", ICRA 2015) for the image update of the
// joint angles (paper Eq. (13) and Sec. "Posterior in the angle";
// docs/method.md "Coordinate Particle Filter").
//
// Target: the posterior p(x | image) ∝ p(image | x) prod_j N(x_j; m_j, s_j^2)
// over n coordinates (joint angles, virtual joints) with a factorised
// Gaussian prior. One run:
//   1. L particles start at the prior mean m, with uniform weights.
//   2. For each sampling block k in order (a named group of coordinates):
//      - if the weights have degenerated, KL(w || uniform) > max_kl_divergence,
//        resample them (systematic resampling) to uniform weights;
//      - perturb the block: x_j <- m_j + scale s_j eps, eps ~ N(0, 1), for
//        every particle and every coordinate j of the block, i.e. draw the
//        block from its prior marginal (the paper's proposal is the process
//        model, here the Gaussian prior);
//      - multiply each particle's weight by its likelihood ratio
//        p(image | x after) / p(image | x before), i.e. add the change in its
//        log-likelihood to its log-weight.
//   3. Moment-match: weighted mean and variance of every coordinate (Eqs.
//      (15)-(16), with weights instead of a final resampling): with the
//      final weights, or, for a block the image informed only weakly, with
//      the weights right after its own ratios (block_moments_below_nats).
// A block whose likelihood ratios were all equal (within no_evidence_nats:
// e.g. a joint whose every hypothesis leaves the arm out of view) has seen
// no evidence; its coordinates keep their prior mean and variance exactly.
// Moment-matching them instead would replace the prior by a sample of L
// draws, a random walk of about s / sqrt(L) per image that the joint filters
// would read as evidence about the encoder bias.
// Why this is exact in the limit: after block k the particles target
// p(x_1..k) p(image | x_1..k, m_k+1..n); proposing block k+1 from its prior
// and weighting by the likelihood ratio is the importance weight between two
// consecutive targets, so after the last block the target is the posterior.
// Matched after its own block (block_moments_below_nats), a block is matched under its
// step's target: exact where the likelihood does not couple it to the later
// blocks' coordinates.
// With proposal_scale != 1 the prior standard deviations are scaled in the
// target as well (a less confident prior), not importance-corrected.
//
// Cost: (number of blocks) x L likelihood evaluations per run; the mean
// itself is never evaluated, since a likelihood common to all particles
// cancels in the weights. Deterministic: all random numbers come from the
// caller's generator in the calling thread, the evaluator's results do not
// depend on how particles are split across threads.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "arttrack/tracker/particle_filter_params.h"

namespace arttrack {

class WorkerPool;  // worker_pool.h: threads that split the particles

// What the evaluator is asked for: the log-likelihoods of all particles right
// after one block was perturbed.
struct ParticleBatch {
  int block = 0;                      // index into the filter's blocks, visited 0, 1, ... per run
  std::span<const int> coordinates;   // the coordinates that just changed
  const double* particles = nullptr;  // row-major L x n: particle l at particles + l n
  int num_particles = 0;              // L
  int dimension = 0;                  // n
  // Particle l was copied from particle parents[l] of the previous call by
  // resampling (identity when there was none; at block 0 every particle
  // comes from the prior mean). Lets an evaluator keep per-particle caches, e.g.
  // renders of the links that the current block does not move.
  std::span<const int> parents;

  std::span<const double> particle(int l) const {
    return {particles + std::size_t(l) * dimension, std::size_t(dimension)};
  }
};

// The image log-likelihood of many particles at once (up to an additive
// constant common to all particles and all calls of a run).
class LogLikelihoodEvaluator {
 public:
  virtual ~LogLikelihoodEvaluator() = default;
  // Fills log_likelihood[l] for every particle l; may use `pool` to spread
  // the work. A non-finite value (NaN, +-inf) counts as impossible (-inf).
  virtual void evaluate(const ParticleBatch& batch, std::span<double> log_likelihood,
                        WorkerPool& pool) = 0;
};

// An evaluator written one particle at a time; particles are spread over the
// pool in contiguous chunks.
class PerParticleEvaluator : public LogLikelihoodEvaluator {
 public:
  // Log-likelihood of particle l of the batch. Called concurrently for
  // different particles, with worker in [0, pool.num_workers()) unique among
  // concurrent calls (an index into per-thread workspaces).
  virtual double log_likelihood(const ParticleBatch& batch, int particle, int worker) = 0;

  void evaluate(const ParticleBatch& batch, std::span<double> log_likelihood,
                WorkerPool& pool) final;
};

// KL divergence of normalised weights from the uniform distribution, nats:
// sum_l w_l log(L w_l) = log L - entropy(w) (0 log 0 = 0). 0 for uniform
// weights, log L when one particle has all the weight; for weights uniform
// over k of the L particles it is log(L / k).
double kl_divergence_from_uniform(std::span<const double> weights);

// One CPF over a fixed dimension and block layout; keeps its particles and
// scratch buffers between runs, so a run allocates nothing.
class CoordinateParticleFilter {
 public:
  // Throws InputError (naming the block) for an empty block, a coordinate out
  // of [0, dimension) or in two blocks, or for bad parameters. Coordinates in
  // no block are not sampled: they keep their prior mean and variance.
  CoordinateParticleFilter(int dimension, std::vector<SamplingBlock> blocks,
                           const CoordinateParticleFilterParams& params = {});

  // One update (see top) from the prior N(prior_mean, prior_std^2), factorised
  // over coordinates.
  void run(std::span<const double> prior_mean, std::span<const double> prior_std,
           LogLikelihoodEvaluator& evaluator, std::mt19937_64& rng, WorkerPool& pool);

  // The general run: the target is prior x likelihood^likelihood_exponent,
  // but particles start at proposal_mean and block coordinates are drawn
  // from N(proposal_mean, (proposal_scale proposal_std)^2), each draw
  // weighted by prior / proposal density. The start point is a constant
  // common to all particles, so the CPF's argument (see top) holds for any
  // start point and any proposal that covers the prior: this is how the
  // tracker's annealed passes (tracker.h) search around an earlier pass's
  // result while still targeting the filter's prior. likelihood_exponent in
  // (0, 1] tempers the image: 1 is the pixel model as is; below 1 it counts
  // the pixels as correlated (fewer independent measurements than pixels).
  // The evaluator's begin_run must have been given proposal_mean as the
  // start point.
  void run(std::span<const double> prior_mean, std::span<const double> prior_std,
           std::span<const double> proposal_mean, std::span<const double> proposal_std,
           double likelihood_exponent, LogLikelihoodEvaluator& evaluator, std::mt19937_64& rng,
           WorkerPool& pool);

  int dimension() const { return dimension_; }
  int num_particles() const { return num_particles_; }
  const std::vector<SamplingBlock>& blocks() const { return blocks_; }
  const CoordinateParticleFilterParams& params() const { return params_; }

  // Results of the last run: weighted mean and variance per coordinate.
  std::span<const double> mean() const { return mean_; }
  std::span<const double> variance() const { return variance_; }
  // Per coordinate: 1 when its block saw evidence in the last run, 0 when
  // it kept its prior (no evidence, or in no block).
  std::span<const unsigned char> informed() const { return informed_; }
  // Likelihood evaluations (particles x blocks not held at their mean by a
  // proposal spread of 0), resamplings, and blocks after which every
  // particle was impossible (weights were then reset to uniform, i.e. that
  // block's image evidence ignored).
  int num_evaluations() const { return num_evaluations_; }
  int num_resamplings() const { return num_resamplings_; }
  int num_degenerate_blocks() const { return num_degenerate_; }
  // Final particles (row-major L x n), normalised weights, and effective
  // sample size 1 / sum w^2.
  std::span<const double> particles() const { return particles_; }
  std::span<const double> weights() const { return weights_; }
  double effective_sample_size() const;
  // Tempered log-likelihood of the heaviest final particle (relative to the
  // start point, which scores 0).
  double best_log_likelihood() const { return best_log_likelihood_; }

 private:
  void normalise_weights();  // log_weights_ -> weights_
  void resample(std::mt19937_64& rng);
  void moment_match(int coordinate);  // mean_ and variance_ from weights_

  int dimension_ = 0;
  int num_particles_ = 0;
  std::vector<SamplingBlock> blocks_;
  CoordinateParticleFilterParams params_;
  std::vector<bool> sampled_;  // coordinate is in some block

  std::vector<double> particles_, scratch_particles_;
  std::vector<double> log_weights_, weights_;
  std::vector<double> log_likelihood_, new_log_likelihood_, scratch_log_likelihood_;
  std::vector<double> correction_;  // per particle: log prior - log proposal of the block's draw
  double best_log_likelihood_ = 0;
  std::vector<int> parents_;
  std::vector<double> mean_, variance_;
  std::vector<unsigned char> informed_;
  // Moment-matched after its own block in the last run (never set for a
  // coordinate in no block).
  std::vector<unsigned char> matched_;
  int num_evaluations_ = 0;
  int num_resamplings_ = 0;
  int num_degenerate_ = 0;
};

}  // namespace arttrack
