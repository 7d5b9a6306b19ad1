#include "arttrack/tracker/internal/coordinate_particle_filter.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <thread>

#include "../expect_error.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/worker_pool.h"

namespace arttrack {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// y = H x + N(0, R) with a 6-D state in three blocks; the likelihood couples
// coordinates across blocks.
struct LinearGaussianProblem {
  static constexpr int n = 6;
  static constexpr int m = 4;
  Eigen::VectorXd prior_mean = Eigen::VectorXd(n);
  Eigen::VectorXd prior_std = Eigen::VectorXd(n);
  Eigen::MatrixXd H = Eigen::MatrixXd(m, n);
  Eigen::VectorXd noise_std = Eigen::VectorXd(m);
  Eigen::VectorXd y = Eigen::VectorXd(m);

  LinearGaussianProblem() {
    prior_mean << 0.3, -0.2, 0.5, 0.0, -0.4, 0.1;
    prior_std << 0.5, 0.3, 0.4, 0.6, 0.35, 0.45;
    H << 1.0, 0.5, 0.0, 0.2, 0.0, 0.0,  //
        0.0, 1.0, 0.8, 0.0, 0.3, 0.0,   //
        0.3, 0.0, 0.0, 1.0, 0.0, 0.7,   //
        0.0, 0.0, 0.5, 0.0, 1.0, 0.6;
    noise_std << 0.25, 0.3, 0.35, 0.3;
    y << 0.6, 0.1, 0.2, -0.5;
  }

  // Closed-form posterior with the prior std scaled by `scale`.
  void posterior(double scale, Eigen::VectorXd& mean, Eigen::MatrixXd& cov) const {
    const Eigen::VectorXd prior_var = (scale * prior_std).array().square();
    const Eigen::MatrixXd R_inv = noise_std.array().square().inverse().matrix().asDiagonal();
    const Eigen::MatrixXd info =
        Eigen::MatrixXd(prior_var.cwiseInverse().asDiagonal()) + H.transpose() * R_inv * H;
    cov = info.inverse();
    mean = cov * (prior_var.cwiseInverse().cwiseProduct(prior_mean) + H.transpose() * R_inv * y);
  }
};

class GaussianEvaluator : public PerParticleEvaluator {
 public:
  explicit GaussianEvaluator(const LinearGaussianProblem& p) : p_(p) {}
  double log_likelihood(const ParticleBatch& batch, int l, int) override {
    const std::span<const double> x = batch.particle(l);
    const Eigen::Map<const Eigen::VectorXd> xv(x.data(), x.size());
    const Eigen::VectorXd res = (p_.y - p_.H * xv).cwiseQuotient(p_.noise_std);
    return -0.5 * res.squaredNorm();
  }

 private:
  const LinearGaussianProblem& p_;
};

std::vector<SamplingBlock> three_blocks() {
  return {{"upper", {0, 1}}, {"lower", {2, 3}}, {"head", {4, 5}}};
}

// Runs the CPF with many seeds and checks the average of the estimated
// means and variances against the closed form with a tolerance from the
// run-to-run spread: 4.5 standard errors of the average over the runs (one
// of the 12 statistics exceeding it by chance: about 1e-4). The estimator's
// bias decays as 1/L while that tolerance decays as 1/sqrt(L runs), so L is
// large: at L = 2000 the bias of the harder case (scale 1.5, final effective
// sample size 9% of L) is still about 5 standard errors of 40 runs; at
// L = 20000 it is below one.
// With block_moments, each block is matched under its own step's target,
// not the posterior: the problem's coupling across blocks would show.
void expect_matches_kalman_posterior(double scale, bool block_moments = false) {
  const LinearGaussianProblem problem;
  Eigen::VectorXd mean;
  Eigen::MatrixXd cov;
  problem.posterior(scale, mean, cov);
  CoordinateParticleFilterParams params;
  params.num_particles = 20000;
  params.proposal_scale = scale;
  params.block_moments_below_nats = block_moments ? kInfinity : 0.0;
  CoordinateParticleFilter cpf(problem.n, three_blocks(), params);
  GaussianEvaluator evaluator(problem);
  WorkerPool pool(2);
  const int runs = 20;
  Eigen::MatrixXd means(runs, problem.n), vars(runs, problem.n);
  const std::vector<double> m(problem.prior_mean.data(), problem.prior_mean.data() + problem.n);
  const std::vector<double> s(problem.prior_std.data(), problem.prior_std.data() + problem.n);
  for (int k = 0; k < runs; ++k) {
    std::mt19937_64 rng(1000 + k);
    cpf.run(m, s, evaluator, rng, pool);
    EXPECT_EQ(cpf.num_evaluations(), 3 * params.num_particles);
    for (int c = 0; c < problem.n; ++c) {
      means(k, c) = cpf.mean()[c];
      vars(k, c) = cpf.variance()[c];
    }
  }
  for (int c = 0; c < problem.n; ++c) {
    const double avg_mean = means.col(c).mean();
    const double sd_mean = std::sqrt((means.col(c).array() - avg_mean).square().sum() / (runs - 1));
    const double avg_var = vars.col(c).mean();
    const double sd_var = std::sqrt((vars.col(c).array() - avg_var).square().sum() / (runs - 1));
    EXPECT_NEAR(avg_mean, mean(c), 4.5 * sd_mean / std::sqrt(runs)) << "coordinate " << c;
    EXPECT_NEAR(avg_var, cov(c, c), 4.5 * sd_var / std::sqrt(runs)) << "coordinate " << c;
    // And the filter is useful: one run's mean is within a fifth of the
    // posterior standard deviation (an effective sample size above 25).
    EXPECT_LT(sd_mean, 0.2 * std::sqrt(cov(c, c))) << "coordinate " << c;
    // The image did something: the posterior is narrower than the prior.
    EXPECT_LT(cov(c, c), 0.8 * std::pow(scale * problem.prior_std(c), 2));
  }
}

TEST(CoordinateParticleFilter, MatchesKalmanPosteriorOfLinearGaussianModel) {
  expect_matches_kalman_posterior(1.0);
}

TEST(CoordinateParticleFilter, ProposalScaleWidensThePrior) {
  expect_matches_kalman_posterior(1.5);
}

// Matched right after its own ratios, a block the likelihood does not
// couple to the later ones is matched to the posterior too.
TEST(CoordinateParticleFilter, BlockMomentsMatchThePosteriorOfUncoupledBlocks) {
  LinearGaussianProblem problem;
  problem.H << 1.0, 0.5, 0.0, 0.0, 0.0, 0.0,  //
      0.0, 1.0, 0.0, 0.0, 0.0, 0.0,           //
      0.0, 0.0, 0.8, 1.0, 0.0, 0.0,           //
      0.0, 0.0, 0.0, 0.0, 1.0, 0.6;
  Eigen::VectorXd mean;
  Eigen::MatrixXd cov;
  problem.posterior(1.0, mean, cov);
  CoordinateParticleFilterParams params;
  params.block_moments_below_nats = kInfinity;
  params.num_particles = 20000;
  CoordinateParticleFilter cpf(problem.n, three_blocks(), params);
  GaussianEvaluator evaluator(problem);
  WorkerPool pool(2);
  const std::vector<double> m(problem.prior_mean.data(), problem.prior_mean.data() + problem.n);
  const std::vector<double> s(problem.prior_std.data(), problem.prior_std.data() + problem.n);
  std::mt19937_64 rng(7);
  cpf.run(m, s, evaluator, rng, pool);
  for (int c = 0; c < problem.n; ++c) {
    // 20000 draws of the prior weighted to a posterior at least a third as
    // wide: a mean within a few hundredths of the posterior's sigma.
    EXPECT_NEAR(cpf.mean()[c], mean(c), 0.05 * std::sqrt(cov(c, c))) << c;
    EXPECT_NEAR(cpf.variance()[c], cov(c, c), 0.1 * cov(c, c)) << c;
  }
}

// A coordinate the likelihood barely informs, sampled before a sharp one:
// the sharp block's weights pick a few of the first coordinate's draws at
// random. Matched with the final weights, its mean is then about s /
// sqrt(ESS) off from run to run and its variance collapses; matched after
// its own block, it is within about s / sqrt(L) and keeps its width.
TEST(CoordinateParticleFilter, BlockMomentsAreNotMovedByALaterSharpBlock) {
  struct WeakThenSharp : PerParticleEvaluator {
    double log_likelihood(const ParticleBatch& batch, int l, int) override {
      const double weak = (batch.particle(l)[0] - 0.3) / 2.0;    // prior sd 0.5
      const double sharp = (batch.particle(l)[1] + 0.2) / 0.02;  // prior sd 0.5
      return -0.5 * (weak * weak + sharp * sharp);
    }
  } evaluator;
  // Closed form for coordinate 0: precision 1/0.25 + 1/4, mean 0.3/4 / that.
  const double post_var = 1 / (1 / 0.25 + 1 / 4.0), post_mean = 0.3 / 4 * post_var;
  const std::vector<double> m = {0.0, 0.0}, s = {0.5, 0.5};
  auto spread = [&](bool block_moments, double& rms_error, double& mean_variance) {
    CoordinateParticleFilterParams params;
    params.num_particles = 20;
    params.block_moments_below_nats = block_moments ? kInfinity : 0.0;
    CoordinateParticleFilter cpf(2, {{"weak", {0}}, {"sharp", {1}}}, params);
    WorkerPool pool(1);
    std::mt19937_64 rng(3);
    const int runs = 400;
    double sum_sq = 0, sum_var = 0;
    for (int k = 0; k < runs; ++k) {
      cpf.run(m, s, evaluator, rng, pool);
      sum_sq += std::pow(cpf.mean()[0] - post_mean, 2);
      sum_var += cpf.variance()[0];
    }
    rms_error = std::sqrt(sum_sq / runs);
    mean_variance = sum_var / runs;
  };
  double final_rms = 0, final_var = 0, block_rms = 0, block_var = 0;
  spread(false, final_rms, final_var);
  spread(true, block_rms, block_var);
  const double post_sd = std::sqrt(post_var);
  // s / sqrt(L) is 0.23 of the posterior's sigma; the final weights' ESS
  // after a block 25 times sharper than its prior is about 1-2 (measured:
  // 0.23 and 0.91 of it).
  EXPECT_LT(block_rms, 0.35 * post_sd) << "final weights: " << final_rms;
  EXPECT_GT(final_rms, 0.6 * post_sd);
  EXPECT_GT(block_var, 0.7 * post_var);
  EXPECT_LT(final_var, 0.3 * post_var);
}

// The threshold picks per block: a block whose ratios span less than it is
// matched after its own ratios (as with .inf), every other one with the
// final weights (as with 0). Same seed, same draws, so the moments agree
// exactly coordinate by coordinate.
TEST(CoordinateParticleFilter, BlockMomentsThresholdPicksTheWeakBlocksOnly) {
  struct WeakSharpSharp : PerParticleEvaluator {
    double log_likelihood(const ParticleBatch& batch, int l, int) override {
      const std::span<const double> x = batch.particle(l);
      const double weak = (x[0] - 0.3) / 2.0;  // spans about a nat over the prior
      const double sharp = (x[1] + 0.2) / 0.05, sharper = (x[2] - 0.1) / 0.02;
      return -0.5 * (weak * weak + sharp * sharp + sharper * sharper);
    }
  } evaluator;
  const std::vector<double> m = {0.0, 0.0, 0.0}, s = {0.5, 0.5, 0.5};
  auto moments = [&](double below_nats) {
    CoordinateParticleFilterParams params;
    params.num_particles = 50;
    params.block_moments_below_nats = below_nats;
    CoordinateParticleFilter cpf(3, {{"weak", {0}}, {"sharp", {1}}, {"sharper", {2}}}, params);
    WorkerPool pool(1);
    std::mt19937_64 rng(11);
    cpf.run(m, s, evaluator, rng, pool);
    std::vector<double> r(cpf.mean().begin(), cpf.mean().end());
    r.insert(r.end(), cpf.variance().begin(), cpf.variance().end());
    return r;
  };
  const std::vector<double> never = moments(0), always = moments(kInfinity), some = moments(20);
  // Weak (coordinate 0: mean, variance at 0 and 3) as after its own block.
  EXPECT_EQ(some[0], always[0]);
  EXPECT_EQ(some[3], always[3]);
  EXPECT_NE(some[0], never[0]);
  // Sharp (1, followed by a sharper block) with the final weights.
  EXPECT_EQ(some[1], never[1]);
  EXPECT_EQ(some[4], never[4]);
  EXPECT_NE(some[1], always[1]);
  // The last block: the same either way.
  EXPECT_EQ(some[2], never[2]);
  EXPECT_EQ(some[2], always[2]);
}

TEST(CoordinateParticleFilter, SameSeedSameNumbersWhateverTheThreadCount) {
  const LinearGaussianProblem problem;
  CoordinateParticleFilterParams params;
  params.num_particles = 101;  // not a multiple of the worker counts
  CoordinateParticleFilter cpf(problem.n, three_blocks(), params);
  GaussianEvaluator evaluator(problem);
  const std::vector<double> m(problem.prior_mean.data(), problem.prior_mean.data() + problem.n);
  const std::vector<double> s(problem.prior_std.data(), problem.prior_std.data() + problem.n);
  std::vector<std::vector<double>> results;
  for (int workers : {1, 2, 3, 8, 1}) {
    WorkerPool pool(workers);
    std::mt19937_64 rng(42);
    cpf.run(m, s, evaluator, rng, pool);
    std::vector<double> r(cpf.mean().begin(), cpf.mean().end());
    r.insert(r.end(), cpf.variance().begin(), cpf.variance().end());
    results.push_back(r);
  }
  for (size_t i = 1; i < results.size(); ++i) EXPECT_EQ(results[i], results[0]);
  WorkerPool pool(2);
  std::mt19937_64 other(43);
  cpf.run(m, s, evaluator, other, pool);
  EXPECT_NE(std::vector<double>(cpf.mean().begin(), cpf.mean().end()),
            std::vector<double>(results[0].begin(), results[0].begin() + problem.n));
}

TEST(CoordinateParticleFilter, ConstantLikelihoodReturnsThePriorExactly) {
  struct Flat : PerParticleEvaluator {
    double log_likelihood(const ParticleBatch&, int, int) override { return -3.0; }
  } flat;
  CoordinateParticleFilterParams params;
  params.num_particles = 50;
  params.max_kl_divergence = 0;  // would resample at any non-uniformity
  // Coordinate 3 is in no block.
  CoordinateParticleFilter cpf(4, {{"a", {0, 2}}, {"b", {1}}}, params);
  WorkerPool pool(1);
  std::mt19937_64 rng(5);
  const std::vector<double> m = {1.0, -2.0, 0.5, 0.25}, s = {0.1, 0.2, 0.3, 0.4};
  cpf.run(m, s, flat, rng, pool);
  EXPECT_EQ(cpf.num_resamplings(), 0);  // weights stay exactly uniform
  EXPECT_NEAR(cpf.effective_sample_size(), 50, 1e-9);
  // No evidence: not the sample moments of 50 draws, the prior itself.
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(cpf.mean()[c], m[c]) << c;
    EXPECT_DOUBLE_EQ(cpf.variance()[c], s[c] * s[c]) << c;
    EXPECT_EQ(cpf.informed()[c], 0) << c;
  }
}

// A likelihood that depends on coordinate 0 only (block "a"): block "b" saw
// no evidence and keeps its prior exactly, even though the weights it ends
// with are far from uniform; block "a" matches the closed-form posterior.
TEST(CoordinateParticleFilter, BlockWithoutEvidenceKeepsItsPrior) {
  struct OnlyFirst : PerParticleEvaluator {
    double log_likelihood(const ParticleBatch& batch, int l, int) override {
      const double r = (batch.particle(l)[0] - 0.4) / 0.1;
      return -0.5 * r * r;
    }
  } only_first;
  CoordinateParticleFilterParams params;
  params.num_particles = 4000;
  CoordinateParticleFilter cpf(2, {{"a", {0}}, {"b", {1}}}, params);
  WorkerPool pool(2);
  std::mt19937_64 rng(11);
  const std::vector<double> m = {0.0, 1.0}, s = {0.2, 0.3};
  cpf.run(m, s, only_first, rng, pool);
  EXPECT_EQ(cpf.informed()[0], 1);
  EXPECT_EQ(cpf.informed()[1], 0);
  EXPECT_EQ(cpf.mean()[1], 1.0);
  EXPECT_DOUBLE_EQ(cpf.variance()[1], 0.09);
  // Closed form: precision 1/0.04 + 1/0.01 = 125, mean 0.4 * 100 / 125.
  const double post_var = 1.0 / 125, post_mean = 0.4 * 100 / 125;
  const double ess = cpf.effective_sample_size();
  EXPECT_NEAR(cpf.mean()[0], post_mean, 4.5 * std::sqrt(post_var / ess));
  EXPECT_NEAR(cpf.variance()[0], post_var, 4.5 * post_var * std::sqrt(2 / ess));
}

TEST(CoordinateParticleFilter, KlDivergenceFromUniform) {
  const std::vector<double> uniform(8, 1.0 / 8);
  EXPECT_NEAR(kl_divergence_from_uniform(uniform), 0.0, 1e-15);
  std::vector<double> one_hot(8, 0.0);
  one_hot[3] = 1;
  EXPECT_NEAR(kl_divergence_from_uniform(one_hot), std::log(8.0), 1e-15);
  const std::vector<double> half = {0.25, 0, 0.25, 0, 0, 0.25, 0.25, 0};
  EXPECT_NEAR(kl_divergence_from_uniform(half), std::log(2.0), 1e-15);
  const std::vector<double> w = {0.1, 0.2, 0.3, 0.4};
  double kl = 0;
  for (double x : w) kl += x * std::log(x / 0.25);
  EXPECT_NEAR(kl_divergence_from_uniform(w), kl, 1e-15);
}

// Checks the evaluator contract on every call: only the block's coordinates
// changed since the previous call, up to the resampling given by `parents`.
// Block 0 gives each particle a fixed weight; at block 1 the children counts
// must be those of systematic resampling: floor or ceil of L w_l.
class ContractChecker : public LogLikelihoodEvaluator {
 public:
  std::vector<double> previous;
  std::vector<double> block0_log_lik;
  std::vector<int> children;
  int calls = 0;

  void evaluate(const ParticleBatch& batch, std::span<double> out, WorkerPool&) override {
    const int L = batch.num_particles, n = batch.dimension;
    if (batch.block == 0) {
      for (int l = 0; l < L; ++l) {
        for (int c = 0; c < n; ++c) {
          const bool in_block = std::count(batch.coordinates.begin(), batch.coordinates.end(), c);
          if (!in_block) {
            EXPECT_EQ(batch.particle(l)[c], 0.0);  // prior mean
          }
        }
        out[l] = block0_log_lik[l];
      }
    } else {
      children.assign(L, 0);
      for (int l = 0; l < L; ++l) {
        const int parent = batch.parents[l];
        ++children[parent];
        for (int c = 0; c < n; ++c) {
          const bool in_block = std::count(batch.coordinates.begin(), batch.coordinates.end(), c);
          if (!in_block) {
            EXPECT_EQ(batch.particle(l)[c], previous[size_t(parent) * n + c]);
          }
        }
        out[l] = block0_log_lik[parent];  // unchanged: no new evidence
      }
    }
    previous.assign(batch.particles, batch.particles + size_t(L) * n);
    ++calls;
  }
};

TEST(CoordinateParticleFilter, ResamplesSystematicallyAndTellsTheEvaluatorTheParents) {
  const int L = 50;
  CoordinateParticleFilterParams params;
  params.num_particles = L;
  params.max_kl_divergence = 0.1;
  CoordinateParticleFilter cpf(3, {{"a", {1}}, {"b", {0, 2}}}, params);
  ContractChecker checker;
  std::mt19937_64 weights_rng(8);
  std::uniform_real_distribution<double> u(-3, 0);
  for (int l = 0; l < L; ++l) checker.block0_log_lik.push_back(u(weights_rng));
  checker.block0_log_lik[7] = -std::numeric_limits<double>::infinity();  // impossible
  checker.block0_log_lik[9] = std::nan("");                              // counts as impossible
  double sum = 0;
  std::vector<double> w(L);
  for (int l = 0; l < L; ++l) sum += w[l] = std::exp(checker.block0_log_lik[l]);
  w[7] = w[9] = 0;
  sum = std::accumulate(w.begin(), w.end(), 0.0);
  for (double& x : w) x /= sum;
  ASSERT_GT(kl_divergence_from_uniform(w), 0.1);

  WorkerPool pool(1);
  for (int seed = 0; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    const std::vector<double> m = {0, 0, 0}, s = {1, 1, 1};
    cpf.run(m, s, checker, rng, pool);
    EXPECT_EQ(cpf.num_resamplings(), 1);
    EXPECT_EQ(checker.children[7], 0);
    EXPECT_EQ(checker.children[9], 0);
    for (int l = 0; l < L; ++l) {
      EXPECT_GE(checker.children[l], int(std::floor(L * w[l])));
      EXPECT_LE(checker.children[l], int(std::ceil(L * w[l])));
    }
    // After the resampling the weights were reset, and block 1 did not
    // change any log-likelihood.
    EXPECT_NEAR(cpf.effective_sample_size(), L, 1e-9);
  }
  EXPECT_EQ(checker.calls, 40);
}

TEST(CoordinateParticleFilter, NoResamplingWithInfiniteBound) {
  const LinearGaussianProblem problem;
  CoordinateParticleFilterParams params;
  params.num_particles = 200;
  params.max_kl_divergence = std::numeric_limits<double>::infinity();
  CoordinateParticleFilter cpf(problem.n, three_blocks(), params);
  GaussianEvaluator evaluator(problem);
  WorkerPool pool(1);
  std::mt19937_64 rng(3);
  const std::vector<double> m(problem.prior_mean.data(), problem.prior_mean.data() + problem.n);
  const std::vector<double> s(problem.prior_std.data(), problem.prior_std.data() + problem.n);
  cpf.run(m, s, evaluator, rng, pool);
  EXPECT_EQ(cpf.num_resamplings(), 0);
  params.max_kl_divergence = 0;
  CoordinateParticleFilter always(problem.n, three_blocks(), params);
  always.run(m, s, evaluator, rng, pool);
  EXPECT_EQ(always.num_resamplings(), 2);  // before blocks 2 and 3
}

TEST(CoordinateParticleFilter, AllParticlesImpossibleIgnoresTheBlock) {
  struct Impossible : PerParticleEvaluator {
    double log_likelihood(const ParticleBatch&, int, int) override {
      return -std::numeric_limits<double>::infinity();
    }
  } impossible;
  CoordinateParticleFilterParams params;
  params.num_particles = 10;
  CoordinateParticleFilter cpf(2, {{"a", {0}}, {"b", {1}}}, params);
  WorkerPool pool(2);
  std::mt19937_64 rng(1);
  const std::vector<double> m = {0, 0}, s = {1, 1};
  cpf.run(m, s, impossible, rng, pool);
  EXPECT_EQ(cpf.num_degenerate_blocks(), 2);
  for (double x : cpf.mean()) EXPECT_TRUE(std::isfinite(x));
  for (double x : cpf.variance()) EXPECT_TRUE(std::isfinite(x));
}

TEST(CoordinateParticleFilter, EvaluatorExceptionsReachTheCaller) {
  struct Throwing : PerParticleEvaluator {
    double log_likelihood(const ParticleBatch&, int l, int) override {
      if (l == 37) throw std::runtime_error("render failed");
      return 0;
    }
  } throwing;
  CoordinateParticleFilterParams params;
  params.num_particles = 64;
  CoordinateParticleFilter cpf(1, {{"a", {0}}}, params);
  WorkerPool pool(4);
  std::mt19937_64 rng(1);
  const std::vector<double> m = {0}, s = {1};
  EXPECT_THROW(cpf.run(m, s, throwing, rng, pool), std::runtime_error);
  // The pool still works afterwards.
  std::atomic<int> count{0};
  pool.parallel_for(100, [&](int b, int e, int) { count += e - b; });
  EXPECT_EQ(count.load(), 100);
}

TEST(WorkerPool, CoversEveryIndexOnceInChunksOfTheGrain) {
  for (int workers : {1, 2, 3, 7}) {
    WorkerPool pool(workers);
    EXPECT_EQ(pool.num_workers(), workers);
    for (int grain : {1, 3}) {
      for (int n : {0, 1, 5, 6, 100, 1001}) {
        std::vector<std::atomic<int>> hits(n);
        pool.parallel_for(
            n,
            [&](int b, int e, int w) {
              EXPECT_GE(w, 0);
              EXPECT_LT(w, workers);
              EXPECT_LT(b, e);
              if (workers > 1) {  // one worker runs [0, n) in one call
                EXPECT_EQ(b % grain, 0);
                EXPECT_LE(e - b, grain);
              }
              for (int i = b; i < e; ++i) ++hits[i];
            },
            grain);
        for (int i = 0; i < n; ++i) EXPECT_EQ(hits[i].load(), 1) << i;
      }
    }
  }
}

// A chunk that waits until every other index is done finishes only if the
// other thread takes them all: chunks are taken as threads get free, not
// fixed per thread (index 0 would hold indices 1-4 on its own thread).
TEST(WorkerPool, ADelayedChunkDoesNotHoldTheOthers) {
  WorkerPool pool(2);
  constexpr int n = 10;
  std::atomic<int> others_done{0};
  bool all_others_done = false;
  pool.parallel_for(n, [&](int b, int e, int) {
    for (int i = b; i < e; ++i) {
      if (i == 0) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (others_done.load() < n - 1 && std::chrono::steady_clock::now() < deadline)
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        all_others_done = others_done.load() == n - 1;
      } else {
        ++others_done;
      }
    }
  });
  EXPECT_TRUE(all_others_done);
}

TEST(CoordinateParticleFilter, RejectsBadBlocks) {
  EXPECT_THROW(CoordinateParticleFilter(3, {}), InputError);
  EXPECT_THROW(CoordinateParticleFilter(3, {{"empty", {}}}), InputError);
  test_support::expect_error_naming(
      [] {
        CoordinateParticleFilter(3, {{"arm", {0, 1}}, {"head", {1, 2}}});
      },
      "head");
  test_support::expect_error_naming(
      [] {
        CoordinateParticleFilter(3, {{"camera", {0, 3}}});
      },
      "camera");
  CoordinateParticleFilterParams bad;
  bad.num_particles = 0;
  EXPECT_THROW(CoordinateParticleFilter(1, {{"a", {0}}}, bad), InputError);
  CoordinateParticleFilterParams negative;
  negative.no_evidence_nats = -1;
  EXPECT_THROW(CoordinateParticleFilter(1, {{"a", {0}}}, negative), InputError);
}

TEST(WorkerPool, RefusesMoreThanTheBound) {
  const std::string message =
      test_support::error_of([] { WorkerPool pool(kMaxWorkerThreads + 1); });
  EXPECT_NE(message.find(std::to_string(kMaxWorkerThreads)), std::string::npos) << message;
}

}  // namespace
}  // namespace arttrack
