// The particle filter over one depth image (paper Sec. IV-B; docs/method.md,
// "Image update") and what it scores hypotheses with: the pixel model
// holding the image at the likelihood's resolution, the coordinate particle
// filter with the evaluator that draws its hypotheses, the random draws,
// the worker threads, and the robot drawn for the image's camera
// (render_geometry.h). The plain image update runs it from the prior, the
// acquisition's final pass from a search's proposal (acquisition.h), and
// the searches and the refinement score single configurations with it.
//
// Setup: the sampling blocks and the likelihood exponent (from the
// TrackerSetup). Workspace: the rest, changed by every run. Internal to the
// tracker (tracker/internal: not installed). Not thread-safe: the image
// thread's.
#pragma once

#include <memory>
#include <random>
#include <span>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/internal/coordinate_particle_filter.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/internal/hypothesis_evaluator.h"
#include "arttrack/tracker/internal/render_geometry.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/internal/worker_pool.h"

namespace arttrack {

class ImageFilter {
 public:
  // The blocks are sampling_blocks(model, config) (tracker.h). The variance
  // floor (particle_filter.bandwidth_factor) is full fusion's only: its bias
  // fold-back is what a collapsed variance pins; the paper's other methods
  // keep its moment matching (with it, camera_offset_only's left hand on
  // arm__constant_bias went from 232 to 253 mm, no better than the encoders).
  explicit ImageFilter(const TrackerSetup& setup);

  // Before an image's runs: the image at the likelihood's resolution and its
  // camera (subsampled_intrinsics). Returns true when the drawn model
  // changed (RenderGeometry::use_camera): what else draws it must be made
  // again.
  bool set_image(const DepthImage& image, const CameraIntrinsics& camera);
  // The camera alone (set_image's second half), e.g. before the first image.
  bool set_camera(const CameraIntrinsics& camera);

  // One run on the image (CoordinateParticleFilter::run): the target is
  // N(prior_mean, prior_std^2) x likelihood^beta, particles start at
  // proposal_mean and are drawn from N(proposal_mean, proposal_std^2).
  void run(std::span<const double> prior_mean, std::span<const double> prior_std,
           std::span<const double> proposal_mean, std::span<const double> proposal_std);
  const CoordinateParticleFilter& filter() const { return cpf_; }

  // The tempered log-likelihood ratio of the image for the robot at q (every
  // DOF): RenderGeometry::score with this image and beta.
  double score(std::span<const double> q) { return geometry_.score(q, likelihood_, beta_); }

  // What the searches (acquisition.h) run their own filters with.
  const CameraIntrinsics& camera() const { return camera_; }
  const DepthLikelihood& likelihood() const { return likelihood_; }
  double likelihood_exponent() const { return beta_; }
  RenderGeometry& geometry() { return geometry_; }
  const RenderGeometry& geometry() const { return geometry_; }
  std::mt19937_64& rng() { return rng_; }
  WorkerPool& pool() { return pool_; }

 private:
  // Setup.
  double beta_;  // likelihood_exponent
  // Workspace.
  WorkerPool pool_;
  CoordinateParticleFilter cpf_;
  std::unique_ptr<HypothesisEvaluator> evaluator_;
  DepthLikelihood likelihood_;
  std::mt19937_64 rng_;
  RenderGeometry geometry_;
  CameraIntrinsics camera_;
};

}  // namespace arttrack
