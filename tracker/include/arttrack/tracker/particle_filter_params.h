// The Coordinate Particle Filter's settings, as configured: the blocks of
// coordinates it samples together, particles per block, when to resample,
// the proposal's width and where each block's moments are taken. The filter itself is internal
// (coordinate_particle_filter.h, which explains each setting's effect).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace arttrack {

// A named group of coordinates perturbed together (e.g. "upper_arm",
// "camera_offset", or one joint).
struct SamplingBlock {
  std::string name;
  std::vector<int> coordinates;
};

struct CoordinateParticleFilterParams {
  // Number of particles L.
  int num_particles = 20;
  // Resample before perturbing the next block when the KL divergence of the
  // weights from uniform exceeds this, nats. log 2: weights concentrated
  // uniformly on half of the particles. 0: resample after every block (as the
  // CPF paper's algorithm); infinity: never.
  double max_kl_divergence = 0.69314718055994531;
  // Factor on the prior standard deviations when perturbing (coordinate_particle_filter.h).
  double proposal_scale = 1.0;
  // A block whose log-likelihood ratios span at most this, nats, over the
  // possible particles has seen no evidence (coordinate_particle_filter.h).
  double no_evidence_nats = 1e-6;
  // L particles drawn with standard deviation s resolve the posterior no
  // finer than a kernel density estimate's bandwidth, h = bandwidth_factor
  // L^(-1/5) s (Silverman's rule of thumb: 1.06). The moment-matched
  // standard deviation of an informed coordinate is at least h: when the
  // weights collapse onto one particle its variance says nothing, and a
  // variance of 0 would pin the joint's bias (and claim a certainty the
  // particles never had). Capped at the prior's standard deviation (factor
  // 2 without the cap: the camera offset ran away by metres). 0: no floor
  // (the paper's moment matching, the default: with 1.06 the default
  // scenario's 2-sigma coverage of angles went from 0% to 58%, but under the
  // occlusion of occlusion__no_bias the hidden hand's error went from p50
  // 6.6 / p99 38.8 mm to 38.3 / 82.4 mm, worse than encoders only).
  double bandwidth_factor = 0.0;
  // Where a block's coordinates are moment-matched (step 3): a block whose
  // own likelihood ratios span less than block_moments_below_nats is
  // matched right after them, every other block with the final weights.
  // 0 matches every block with the final weights, as the paper; .inf every
  // block after its own ratios. Why: the blocks after a coordinate's own
  // reweight and resample the particles by evidence about other coordinates
  // (the camera's blocks come last and are sharp); for a coordinate the
  // image barely informs (a joint behind an occluder, whose ratios span a
  // few nats) that picks a few of its prior draws at random, so its final
  // moments are a draw about s / sqrt(ESS) off the prior mean with a
  // collapsed variance, which the joint filters read as evidence about the
  // bias. Matched after its own block it keeps the prior's width, but it
  // loses the later blocks' evidence about it through the likelihood's
  // coupling: a hand sampled before the shoulder is matched to the
  // shoulder's prior mean, which before the biases are learned is degrees
  // off. A block the image tells apart while its prior is wide (a shoulder
  // or elbow in view, any joint before its bias is learned) spans tens to
  // hundreds of nats, so the threshold keeps the later blocks' say there.
  // docs/accuracy.md "Moments after weakly informed blocks": with 20, the
  // paper's 36 files were lost in 0 of 180 runs (5 of the 30 runs of the
  // six hard files with 0) and the default scenario at 640x480 in none of
  // 10 (.inf: 1 of 3).
  double block_moments_below_nats = 20;

  // Throws ConfigKeyError (error.h) naming `source` and the key, `prefix`
  // followed by the field's YAML name (num_particles is "particles"), for a
  // value outside its range: particles in [1, 1e6], max_kl_divergence in
  // [0, inf], proposal_scale in [1e-6, 1e6], no_evidence_nats in [0, inf],
  // bandwidth_factor in [0, 10], block_moments_below_nats in [0, inf].
  void validate(std::string_view source, const std::string& prefix = "") const;
};

}  // namespace arttrack
