#include "arttrack/tracker/internal/image_update.h"

#include <algorithm>
#include <cmath>

#include "health_check.h"

namespace arttrack {

ImageUpdate::ImageUpdate(const TrackerSetup& setup)
    : setup_(setup),
      filter_(setup),
      health_check_(std::make_unique<HealthCheck>(*setup.model, setup.n_phys, setup.config.health,
                                                  setup.config.depth_model.max_range_m)),
      health_(health_check_->initial_health()),
      acquisition_(setup),
      covariance_(setup, filter_.filter().blocks()),
      refinement_(setup, covariance_.setup().states),
      unseen_joints_(setup, covariance_.setup().dofs),
      end_effector_fit_(setup),
      axis_search_(*setup.model, end_effector_fit_.fit_links(),
                   end_effector_fit_.on() ? setup.config.end_effector_fit.axis_search_range_m : 0,
                   setup.config.end_effector_fit.max_std_m),
      carrier_motion_(*setup.model, *setup.filter_model, setup.config),
      prior_mean_(std::size_t(setup.n), 0.0),
      prior_std_(std::size_t(setup.n), 0.0),
      carrier_added_var_(std::size_t(setup.n), 0.0),
      mean_fitted_(std::size_t(setup.n), 0.0),
      reopened_(std::size_t(setup.n), 0),
      proposal_std_(std::size_t(setup.n), 0.0) {
  if (end_effector_fit_.on())
    covariance_.set_rigid_fit_links(*setup.model, end_effector_fit_.fit_links());
  const std::vector<SamplingBlock>& blocks = filter_.filter().blocks();
  for (std::size_t b = 0; b < blocks.size(); ++b)
    if (is_camera_block(blocks[b], *setup.model)) camera_blocks_.push_back(int(b));
  // The camera blocks among blocks_sampled_per_image(): the other blocks
  // are sampled at every image.
  camera_blocks_per_image_ = blocks_sampled_per_image(blocks, *setup.model, setup.config) -
                             (int(blocks.size()) - int(camera_blocks_.size()));
}

ImageUpdate::~ImageUpdate() = default;

CameraIntrinsics ImageUpdate::likelihood_camera(const CameraIntrinsics& camera) const {
  return subsampled_intrinsics(camera, filter_.likelihood().width(), filter_.likelihood().height());
}

std::span<const double> ImageUpdate::proposal_std_in_turn() {
  const int count = int(camera_blocks_.size());
  if (camera_blocks_per_image_ >= count) return prior_std_;
  std::copy(prior_std_.begin(), prior_std_.end(), proposal_std_.begin());
  const std::vector<SamplingBlock>& blocks = filter_.filter().blocks();
  const int turn = images_seen_ * camera_blocks_per_image_ % count;
  for (int k = camera_blocks_per_image_; k < count; ++k) {
    const int b = camera_blocks_[std::size_t((turn + k) % count)];
    for (int c : blocks[std::size_t(b)].coordinates) proposal_std_[std::size_t(c)] = 0;
  }
  return proposal_std_;
}

void ImageUpdate::prepare(const CameraIntrinsics& camera) {
  prepare_fit_view(camera);
  if (!filter_.set_camera(likelihood_camera(camera))) return;
  acquisition_.draw(filter_.geometry());
  ++geometry_builds_;
}

bool ImageUpdate::fit_image_size(int width, int height, int& fit_width, int& fit_height) const {
  if (!end_effector_fit_.on()) return false;
  const int factor = setup_.config.end_effector_fit.resolution_factor;
  const int W = filter_.likelihood().width(), H = filter_.likelihood().height();
  fit_width = std::min(W * factor, width);
  fit_height = std::min(H * factor, height);
  return fit_width > W && fit_height > H;
}

bool ImageUpdate::prepare_fit_view(const CameraIntrinsics& full_camera) {
  int width = 0, height = 0;
  if (!fit_image_size(full_camera.width, full_camera.height, width, height)) return false;
  if (!fit_likelihood_ || fit_likelihood_->width() != width ||
      fit_likelihood_->height() != height) {
    DepthModelParams params = setup_.config.depth_model;
    params.width = width;
    params.height = height;
    fit_likelihood_ = std::make_unique<DepthLikelihood>(params);
    fit_geometry_ = std::make_unique<RenderGeometry>(setup_.model, setup_.config.geometry,
                                                     filter_.pool().num_workers());
    fit_information_ = std::make_unique<ImageInformation>(std::vector<int>{});
    fit_information_->set_rigid_fit_links(*setup_.model, end_effector_fit_.fit_links());
  }
  const CameraIntrinsics camera = subsampled_intrinsics(full_camera, width, height);
  if (!fit_geometry_->has_camera(camera)) fit_geometry_->use_camera(camera);
  return true;
}

const std::vector<ImageInformation::RigidFit>* ImageUpdate::fine_rigid_fits(
    const DepthImage& fit_image, const CameraIntrinsics& full_camera) {
  // The image is the camera's size (Tracker::add_depth_image), so its fit
  // image is the size prepare_fit_view() makes the view for.
  if (fit_image.width == 0 || !prepare_fit_view(full_camera)) return nullptr;
  fit_likelihood_->set_observation(fit_image);
  fit_information_->compute(fit_geometry_->renderer(), mean_fitted_, *fit_likelihood_,
                            &filter_.pool());
  return &fit_information_->rigid_fits();
}

double ImageUpdate::apply(const DepthImage& image, const DepthImage& fit_image,
                          const CameraIntrinsics& full_camera, double stamp_s, double time_s,
                          std::span<const double> reading_at_time, JointBelief& belief) {
  const int n = setup_.n;
  // The camera offset's walk with the head that carries it, before the
  // image samples it.
  if (carrier_motion_.on()) {
    carrier_motion_.added_variance(belief.mean_a, carrier_added_var_);
    for (int j = 0; j < n; ++j) belief.var_a[j] += carrier_added_var_[j];
  }
  for (int j = 0; j < n; ++j) prior_std_[j] = std::sqrt(std::max(0.0, belief.var_a[j]));
  std::copy(belief.mean_a.begin(), belief.mean_a.end(), prior_mean_.begin());
  const DepthLikelihood& likelihood = filter_.likelihood();
  if (filter_.set_image(image, likelihood_camera(full_camera))) {
    acquisition_.draw(filter_.geometry());
    ++geometry_builds_;
  }
  double search_ms = 0;
  const bool first = images_seen_++ == 0;
  bool unseen_found = false;  // UnseenJoints::find() ran on this image's prior
  if (acquisition_.on() && first) {
    search_ms = acquisition_.acquire_first(filter_, image, prior_std_, time_s, belief, health_);
  } else {
    unseen_found = unseen_joints_.on();
    if (unseen_found) unseen_joints_.find(belief, filter_.geometry().renderer(), image);
    filter_.run(belief.mean_a, prior_std_, belief.mean_a, proposal_std_in_turn());
    fold_angle_posteriors(filter_.filter().mean(), filter_.filter().variance(), belief);
  }
  HealthCheck& check = *health_check_;
  if (acquisition_.on() && !first && !reading_at_time.empty()) {
    const SearchKind kind = acquisition_.due_search(check, time_s);
    if (kind != SearchKind::kNone) {
      acquisition_.reacquire(kind, filter_, image, check, reading_at_time, time_s, belief, health_,
                             reopened_);
      unseen_found = false;  // the search's result is its own
      search_ms = health_.last_acquisition_ms;
    }
  }
  DepthRenderer& renderer = filter_.geometry().renderer();
  if (end_effector_fit_.on())
    std::copy(belief.mean_a.begin(), belief.mean_a.end(), mean_fitted_.begin());
  const bool informed = covariance_.begin_image(time_s, prior_std_, reopened_, belief.mean_a,
                                                renderer, likelihood, &filter_.pool());
  if (carrier_motion_.on()) covariance_.add_variance(carrier_added_var_);
  if (unseen_found)
    health_.unseen_priors_kept +=
        unseen_joints_.keep_priors(covariance_.information().pixels_per_dof(), belief);
  if (informed && refinement_.on()) {
    health_.refinements_accepted +=
        refinement_.refine(covariance_.step_bound_covariance(), covariance_.information(),
                           prior_mean_, prior_std_, filter_, belief);
    health_.images_with_unseen_motion += refinement_.unseen_directions() > 0;
  }
  covariance_.end_image(time_s, health_);
  covariance_.record_means(time_s, belief);
  // Not at the first image: its search has just placed the arms.
  if (informed && !first) {
    const std::vector<ImageInformation::RigidFit>* fine = fine_rigid_fits(fit_image, full_camera);
    const std::vector<ImageInformation::RigidFit>& fits =
        fine ? *fine : covariance_.information().rigid_fits();
    std::span<const Eigen::Vector3d> shifts;
    if (axis_search_.on())
      shifts = fine ? axis_search_.search(fit_geometry_->renderer(), *fit_likelihood_, mean_fitted_,
                                          fits)
                    : axis_search_.search(renderer, likelihood, mean_fitted_, fits);
    health_.hand_searches = axis_search_.searched();
    health_.hand_shifts_accepted = axis_search_.accepted();
    link_scales_.resize(health_.links.size());  // sized once
    for (std::size_t g = 0; g < health_.links.size(); ++g) link_scales_[g] = health_.links[g].scale;
    end_effector_fit_.update(time_s, fits, mean_fitted_, belief.mean_a,
                             covariance_.model_error_std_m(), shifts, link_scales_);
  }
  check.update(belief.mean_a, image, stamp_s, renderer, health_);
  return search_ms;
}

}  // namespace arttrack
