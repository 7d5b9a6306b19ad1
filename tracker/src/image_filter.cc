#include "arttrack/tracker/internal/image_filter.h"

#include "arttrack/tracker/tracker.h"

namespace arttrack {
namespace {

CoordinateParticleFilter make_filter(const TrackerSetup& setup) {
  const std::vector<SamplingBlock> blocks = sampling_blocks(*setup.model, setup.config);
  return CoordinateParticleFilter(
      setup.n, blocks,
      particle_filter_params(setup.config,
                             blocks_sampled_per_image(blocks, *setup.model, setup.config)));
}

}  // namespace

ImageFilter::ImageFilter(const TrackerSetup& setup)
    : beta_(setup.config.likelihood_exponent),
      pool_(setup.config.threads),
      cpf_(make_filter(setup)),
      likelihood_(setup.config.depth_model),
      rng_(setup.config.seed),
      geometry_(setup.model, setup.config.geometry, pool_.num_workers()) {}

bool ImageFilter::set_image(const DepthImage& image, const CameraIntrinsics& camera) {
  likelihood_.set_observation(image);
  return set_camera(camera);
}

bool ImageFilter::set_camera(const CameraIntrinsics& camera) {
  camera_ = camera;
  if (geometry_.has_camera(camera) || !geometry_.use_camera(camera)) return false;
  evaluator_ = std::make_unique<HypothesisEvaluator>(geometry_.drawn_model(), cpf_.blocks(),
                                                     HypothesisEvaluator::Mode::kCached,
                                                     geometry_.render_options());
  return true;
}

void ImageFilter::run(std::span<const double> prior_mean, std::span<const double> prior_std,
                      std::span<const double> proposal_mean, std::span<const double> proposal_std) {
  evaluator_->begin_run(camera_, likelihood_, proposal_mean);
  cpf_.run(prior_mean, prior_std, proposal_mean, proposal_std, beta_, *evaluator_, rng_, pool_);
}

}  // namespace arttrack
