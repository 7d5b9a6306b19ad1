#include "arttrack/tracker/internal/reported_covariance.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace arttrack {
namespace {

// A link's scale is reported once this many images have sized it (about a
// second of images): a link seen in a few images, at the view's edge or
// small in it, read up to 6% off on the realistic dual arm.
constexpr int kMinScaleImages = 30;

// A running average of `sample` over `time_constant_s`, from 0: the first
// sample (last_time_s NaN) weighs one image's share (1/30 s), later ones the
// time since the previous.
void average_over_time(double sample, double time_s, double time_constant_s, double& average,
                       double& last_time_s) {
  const double dt = std::isnan(last_time_s) ? 1.0 / 30 : std::max(0.0, time_s - last_time_s);
  const double keep = std::exp(-dt / time_constant_s);
  average = keep * average + (1 - keep) * sample;
  last_time_s = time_s;
}

// The states whose means MeanLag follows: a bias and a camera offset stand
// still once placed; a physical joint's angle (vision only) moves with the
// robot.
std::vector<char> lag_tracked(const ReportedCovarianceSetup& setup) {
  std::vector<char> tracked(setup.states.size(), 0);
  for (std::size_t i = 0; i < tracked.size(); ++i)
    tracked[i] =
        setup.states[i].kind == PosteriorCovariance::Kind::kBias || !setup.physical_joint[i];
  return tracked;
}

}  // namespace

ReportedCovarianceSetup::ReportedCovarianceSetup(const TrackerSetup& setup,
                                                 const std::vector<SamplingBlock>& sampled_blocks)
    : reopened_bias_var_rad2(setup.config.acquisition.bias_std_rad *
                             setup.config.acquisition.bias_std_rad),
      image_information_scale(setup.config.image_information_scale),
      discount_correlated_residuals(setup.config.discount_correlated_residuals),
      pixel_noise_after_fit(setup.config.pixel_noise_after_fit),
      model_error(setup.config.model_error),
      model_error_time_constant_s(setup.config.model_error_time_constant_s),
      model_error_min_std_m(setup.config.model_error_min_std_m),
      model_error_unpinned_scale(setup.config.model_error_unpinned_scale),
      model_error_learned_shifts(setup.config.model_error &&
                                 setup.config.model_error_learned_shifts),
      model_error_learned_time_constant_s(setup.config.model_error_learned_time_constant_s),
      model_error_learned_max_std_m(setup.config.model_error_learned_max_std_m),
      model_error_unpinned_scale_on_learned(setup.config.model_error_unpinned_scale_on_learned),
      mean_lag_scale(setup.config.mean_lag_scale),
      mean_lag_time_constant_s(setup.config.mean_lag_time_constant_s) {
  const JointFilterModel& filter = *setup.filter_model;
  std::vector<char> sampled(setup.n, 0);
  for (const SamplingBlock& b : sampled_blocks)
    for (int j : b.coordinates) sampled[j] = 1;
  for (int j = 0; j < setup.n; ++j) {
    if (!sampled[j]) continue;
    if (j < setup.n_phys && setup.use_encoders) {
      if (!setup.bias_estimated[j]) continue;
      states.push_back({j, PosteriorCovariance::Kind::kBias, filter.bias_decay_rate_per_s()[j],
                        filter.bias_rate_var()[j]});
    } else {
      states.push_back({j, PosteriorCovariance::Kind::kAngle, 0.0, filter.angle_rate_var()[j]});
    }
    dofs.push_back(j);
    physical_joint.push_back(j < setup.n_phys);
    camera_offset.push_back(j >= setup.n_phys);
  }
  link_length_std_m = setup.config.link_length_std_m;
  if (link_length_std_m > 0) find_lengths(*setup.model);
  depth_scale_std = setup.config.depth_scale_std;
  information.link_shifts = model_error || !lengths.empty();
  information.motion_field = true;
  information.depth_scale = depth_scale_std > 0;
  const int links = int(setup.model->links_with_geometry().size());
  first_bulge = (model_error ? 3 * links : 0) + int(lengths.size());
  num_bulges = model_error ? links : 0;
  num_consider = first_bulge + num_bulges + (depth_scale_std > 0 ? 1 : 0);
  // Only the consider analysis has a separate pixel-noise term.
  information.fitted_residuals = pixel_noise_after_fit && num_consider > 0;
}

void ReportedCovarianceSetup::find_lengths(const RobotModel& model) {
  std::vector<char> carries_camera(std::size_t(model.num_links()), 0);
  for (int a = model.camera_link(); a >= 0; a = model.link(a).parent)
    carries_camera[std::size_t(a)] = 1;
  const std::vector<int>& with_geometry = model.links_with_geometry();
  std::vector<char> has_geometry(std::size_t(model.num_links()), 0);
  for (int g : with_geometry) has_geometry[std::size_t(g)] = 1;
  for (int k = 0; k < model.num_links(); ++k) {
    const Link& link = model.link(k);
    const Eigen::Vector3d origin_m = link.T_parent_joint.translation();
    if (link.parent < 0 || carries_camera[std::size_t(k)] || !(origin_m.norm() >= 1e-3)) continue;
    LengthParameter length;
    length.link = k;
    length.parent = link.parent;
    length.direction_in_parent = origin_m.normalized();
    // The shifted links: k if it has geometry, else the links with geometry
    // below k with none between them and k.
    for (std::size_t g = 0; g < with_geometry.size(); ++g) {
      const int top = with_geometry[g];
      if (top == k) length.top_shift_links.push_back(int(g));
      if (top == k || has_geometry[std::size_t(k)]) continue;
      int a = model.link(top).parent;
      while (a >= 0 && a != k && !has_geometry[std::size_t(a)]) a = model.link(a).parent;
      if (a == k) length.top_shift_links.push_back(int(g));
    }
    if (!length.top_shift_links.empty()) lengths.push_back(std::move(length));
  }
}

ReportedCovariance::ReportedCovariance(const TrackerSetup& setup,
                                       const std::vector<SamplingBlock>& sampled)
    : setup_(setup, sampled),
      covariance_(setup_.states, setup_.num_consider),
      information_(setup_.dofs, setup_.information),
      model_(setup.model),
      kinematics_(*setup.model),
      start_(covariance_.size()),
      q_(setup.n),
      mean_lag_(lag_tracked(setup_), setup_.mean_lag_scale, setup_.mean_lag_time_constant_s),
      means_(setup_.states.size(), 0.0) {
  bulge_square_m2_.assign(std::size_t(setup_.num_bulges), 0.0);
  bulge_time_s_.assign(std::size_t(setup_.num_bulges), std::numeric_limits<double>::quiet_NaN());
  if (setup_.model_error_learned_shifts && covariance_.size() > 0)
    learned_ = std::make_unique<LearnedLinkShifts>(int(setup.model->links_with_geometry().size()),
                                                   setup_.model_error_learned_time_constant_s);
  if (learned_ && !setup_.model_error_unpinned_scale_on_learned)
    step_bound_ = std::make_unique<PosteriorCovariance>(setup_.states, setup_.num_consider);
}

bool ReportedCovariance::begin_image(double time_s, std::span<const double> prior_std,
                                     std::vector<char>& reopened, std::span<const double> mean,
                                     DepthRenderer& renderer, const DepthLikelihood& likelihood,
                                     WorkerPool* pool) {
  if (covariance_.size() == 0) return false;
  const auto& states = covariance_.states();
  if (!covariance_.started()) {
    for (int i = 0; i < covariance_.size(); ++i) {
      const double sd = prior_std[states[std::size_t(i)].dof];
      start_[i] = sd * sd;
    }
    covariance_.reset(start_, time_s);
    if (step_bound_) step_bound_->reset(start_, time_s);
  } else {
    covariance_.predict_to(time_s);
    if (step_bound_) step_bound_->predict_to(time_s);
  }
  bool any_reopened = false;
  for (int i = 0; i < covariance_.size(); ++i) {
    const int dof = states[std::size_t(i)].dof;
    if (reopened[dof]) {
      covariance_.restart_state(i, setup_.reopened_bias_var_rad2);
      if (step_bound_) step_bound_->restart_state(i, setup_.reopened_bias_var_rad2);
      mean_lag_.restart(i);
    }
    any_reopened = any_reopened || reopened[dof];
    reopened[dof] = 0;
  }
  for (int j = 0; j < q_.size(); ++j) q_[j] = mean[j];
  information_.compute(renderer, {q_.data(), std::size_t(q_.size())}, likelihood, pool);
  return !any_reopened && information_.pixels_used() > 0;
}

void ReportedCovariance::add_variance(std::span<const double> added_var) {
  const auto& states = covariance_.states();
  for (int i = 0; i < covariance_.size(); ++i) {
    const double v = added_var[std::size_t(states[std::size_t(i)].dof)];
    if (v <= 0) continue;
    covariance_.add_variance(i, v);
    if (step_bound_) step_bound_->add_variance(i, v);
  }
}

void ReportedCovariance::record_means(double time_s, const JointBelief& belief) {
  const auto& states = covariance_.states();
  for (int i = 0; i < covariance_.size(); ++i) {
    const PosteriorCovariance::State& st = states[std::size_t(i)];
    means_[std::size_t(i)] =
        st.kind == PosteriorCovariance::Kind::kBias ? belief.mean_b[st.dof] : belief.mean_a[st.dof];
  }
  mean_lag_.update(time_s, means_);
}

void ReportedCovariance::end_image(double time_s, TrackingHealth& health) {
  if (covariance_.size() == 0) return;
  const Eigen::MatrixXd& info = information_.motion_field_information();
  const double discount =
      setup_.discount_correlated_residuals ? information_.effective_pixel_fraction() : 1.0;
  const double scale = setup_.image_information_scale * discount;
  // The gain applies `scale` to the pixels' noise, which the fitted
  // residuals size at fitted_residual_factor() of the model's: the noise
  // term is scale times that share of the weights' (at most all of it).
  const double noise_scale =
      setup_.information.fitted_residuals
          ? std::clamp(scale * information_.fitted_residual_factor(), 0.0, 1.0)
          : 1.0;
  if (setup_.num_consider == 0) {
    covariance_.update(info, scale);
    return;
  }
  const Eigen::MatrixXd& shift_cross = information_.motion_field_shift_cross_information();
  consider_cross_.resize(info.rows(), setup_.num_consider);
  double std_m = 0, unpinned_std_m = 0;
  if (setup_.model_error) {
    // The link shifts' variance, averaged over time (one image's estimate is
    // noisy, and unbiased: negative samples count, only the average is
    // clipped).
    const double sample = information_.link_shift_variance_m2(
        &pinned_, &column_square_m2_, learned_ ? &shift_equations_ : nullptr, &scale_fits_,
        &bulge_samples_m2_);
    if (learned_) {  // each image's fit weighs its independent pixels' share
      learned_->add_image(time_s, shift_equations_, information_.T_link_camera(), discount);
      learned_->solve();
    }
    // From 0, so that the first images (the estimate still converging, its
    // residuals large) weigh one image's share each.
    average_over_time(sample, time_s, setup_.model_error_time_constant_s, model_error_var_m2_,
                      model_error_time_s_);
    health.model_error_std_m = std::sqrt(std::max(0.0, model_error_var_m2_));
    update_link_model_errors(time_s, health);
    std_m = std::max(health.model_error_std_m, setup_.model_error_min_std_m);
    model_error_std_m_ = std_m;
    // A shift this image does not pin is one the DOFs absorb (arm7's upper-arm
    // length, taken up by the shoulder) or one it hardly sees: the estimate,
    // from the shifts that fit, says least about those (docs/accuracy.md,
    // stop 41). Every state carries such a shift at the scaled estimate.
    // (Stops 42-86 kept the camera offset's at the estimate: scaled, the
    // dual arm's camera went to 99-100% while the bulges inflated the
    // estimate; with them fitted apart it is in the band, stop 87.)
    unpinned_std_m = std::max(std_m, setup_.model_error_unpinned_scale * health.model_error_std_m);
    for (int c = 0; c < shift_cross.cols(); ++c)
      consider_cross_.col(c) =
          shift_cross.col(c) * (pinned_[std::size_t(c)] ? std_m : unpinned_std_m);
    fill_bulge_columns(time_s);
  }
  fill_length_columns(shift_cross);
  if (setup_.depth_scale_std > 0)
    consider_cross_.col(setup_.num_consider - 1) =
        information_.depth_scale_cross_information() * setup_.depth_scale_std;
  if (learned_) {
    widened_cross_ = consider_cross_;
    widen_learned_axes(shift_cross, std_m, unpinned_std_m);
    if (step_bound_) {
      step_bound_cross_ = consider_cross_;
      fill_learned_joint_columns(shift_cross, std_m);
      // With the weights' own pixel noise (not noise_scale): the means stay
      // what they are without pixel_noise_after_fit.
      step_bound_->update(info, step_bound_cross_, widened_cross_, setup_.camera_offset, scale);
    }
    covariance_.update(info, consider_cross_, widened_cross_, setup_.camera_offset, scale,
                       noise_scale);
  } else {
    covariance_.update(info, consider_cross_, scale, noise_scale);
  }
}

void ReportedCovariance::update_link_model_errors(double time_s, TrackingHealth& health) {
  const std::vector<int>& with_geometry = model_->links_with_geometry();
  if (pinned_.size() != 3 * with_geometry.size()) return;  // no shifts computed
  if (health.links.size() != with_geometry.size()) {       // the first image: sized once
    health.links.assign(with_geometry.size(), {});
    for (std::size_t g = 0; g < with_geometry.size(); ++g)
      health.links[g].link = model_->link_name(with_geometry[g]);
    link_square_m2_.assign(with_geometry.size(), 0.0);
    link_time_s_.assign(with_geometry.size(), std::numeric_limits<double>::quiet_NaN());
    scale_weight_.assign(with_geometry.size(), 0.0);
    scale_weighted_.assign(with_geometry.size(), 0.0);
    scale_time_s_.assign(with_geometry.size(), std::numeric_limits<double>::quiet_NaN());
  }
  for (std::size_t g = 0; g < with_geometry.size() && g < scale_fits_.size(); ++g) {
    const ImageInformation::LinkScaleFit& fit = scale_fits_[g];
    if (std::isnan(fit.scale)) continue;
    // A fixed property seen over many poses: the images' fits weighted by
    // their precision, the older ones fading over the learned shifts' time.
    const double dt = std::isnan(scale_time_s_[g]) ? 0.0 : std::max(0.0, time_s - scale_time_s_[g]);
    const double keep = std::exp(-dt / setup_.model_error_learned_time_constant_s);
    scale_weight_[g] = keep * scale_weight_[g] + 1 / fit.noise_var;
    scale_weighted_[g] = keep * scale_weighted_[g] + fit.scale / fit.noise_var;
    scale_time_s_[g] = time_s;
    ++health.links[g].scale_images;
    if (health.links[g].scale_images >= kMinScaleImages)
      health.links[g].scale = scale_weighted_[g] / scale_weight_[g];
  }
  for (std::size_t g = 0; g < with_geometry.size(); ++g) {
    if (!pinned_[3 * g] && !pinned_[3 * g + 1] && !pinned_[3 * g + 2]) continue;
    // The pinned directions' squares (0 where not pinned) add up to the
    // shift's pinned size; averaged as the pooled estimate.
    const double square_m2 =
        column_square_m2_[3 * g] + column_square_m2_[3 * g + 1] + column_square_m2_[3 * g + 2];
    average_over_time(square_m2, time_s, setup_.model_error_time_constant_s, link_square_m2_[g],
                      link_time_s_[g]);
    health.links[g].shift_m = std::sqrt(std::max(0.0, link_square_m2_[g]));
    ++health.links[g].images;
  }
}

bool ReportedCovariance::learned_excess_m2(int k, double std_m, Eigen::Matrix3d& excess_m2) const {
  // The learned shift's excess over the prior, per learned axis of the
  // link: a shift N(0, s^2) learned as p with noise variance v has
  // E[p^2] = s^2 + v, so s^2 is about p^2 - v.
  const double max_var_m2 =
      setup_.model_error_learned_max_std_m * setup_.model_error_learned_max_std_m;
  Eigen::Vector3d excess_link_m2 = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d& covariance_m2 = learned_->covariance_m2(k);
  for (int b = 0; b < 3; ++b)
    if (covariance_m2(b, b) < max_var_m2) {
      const double p_m = learned_->shift_m(k)[b];
      excess_link_m2[b] = std::max(0.0, p_m * p_m - covariance_m2(b, b) - std_m * std_m);
    }
  // Link axis b is row b of R_link_camera in camera axes.
  const Eigen::Matrix3d R = information_.T_link_camera()[std::size_t(k)].linear();
  excess_m2 = R.transpose() * excess_link_m2.asDiagonal() * R;
  return (excess_link_m2.array() > 0).any();
}

void ReportedCovariance::widen_learned_axes(const Eigen::MatrixXd& shift_cross, double std_m,
                                            double unpinned_std_m) {
  Eigen::Matrix3d prior_m2;
  for (int k = 0; k < learned_->num_links(); ++k) {
    if (!learned_excess_m2(k, std_m, prior_m2)) continue;
    for (int a = 0; a < 3; ++a) {
      const double sd = pinned_[std::size_t(3 * k + a)] ? std_m : unpinned_std_m;
      prior_m2(a, a) += sd * sd + 1e-18;  // a floor of (1 nm)^2 keeps the factor defined
    }
    widened_cross_.middleCols<3>(3 * k).noalias() =
        shift_cross.middleCols<3>(3 * k) * Eigen::Matrix3d(prior_m2.llt().matrixL());
  }
}

void ReportedCovariance::fill_learned_joint_columns(const Eigen::MatrixXd& shift_cross,
                                                    double std_m) {
  if (shift_cross.cols() != 3 * learned_->num_links()) return;  // no shifts computed
  const double max_var_m2 =
      setup_.model_error_learned_max_std_m * setup_.model_error_learned_max_std_m;
  Eigen::Matrix3d prior_m2;
  for (int k = 0; k < learned_->num_links(); ++k) {
    if (!(learned_->covariance_m2(k).diagonal().array() < max_var_m2).all()) continue;
    // The excess along the camera axes the image does not pin (rows and
    // columns of the pinned ones zeroed: still a covariance), std_m on all.
    learned_excess_m2(k, std_m, prior_m2);
    for (int a = 0; a < 3; ++a)
      if (pinned_[std::size_t(3 * k + a)]) {
        prior_m2.row(a).setZero();
        prior_m2.col(a).setZero();
      }
    for (int a = 0; a < 3; ++a) prior_m2(a, a) += std_m * std_m + 1e-18;
    consider_cross_.middleCols<3>(3 * k).noalias() =
        shift_cross.middleCols<3>(3 * k) * Eigen::Matrix3d(prior_m2.llt().matrixL());
  }
}

void ReportedCovariance::fill_bulge_columns(double time_s) {
  const Eigen::MatrixXd& bulge_cross = information_.motion_field_bulge_cross_information();
  const int links = setup_.num_bulges;
  if (bulge_cross.cols() != links || std::ssize(bulge_samples_m2_) != links) {
    // Not this model's (an end_image() without its begin_image()): no bulge.
    consider_cross_.middleCols(setup_.first_bulge, links).setZero();
    return;
  }
  for (int l = 0; l < links; ++l) {
    // Each link's own size: a link whose surfaces are its model's (or flat:
    // no bulge) keeps none.
    const double sample_m2 = bulge_samples_m2_[std::size_t(l)];
    if (!std::isnan(sample_m2))
      average_over_time(sample_m2, time_s, setup_.model_error_time_constant_s,
                        bulge_square_m2_[std::size_t(l)], bulge_time_s_[std::size_t(l)]);
    consider_cross_.col(setup_.first_bulge + l) =
        bulge_cross.col(l) * std::sqrt(std::max(0.0, bulge_square_m2_[std::size_t(l)]));
  }
}

void ReportedCovariance::fill_length_columns(const Eigen::MatrixXd& shift_cross) {
  if (setup_.lengths.empty()) return;
  // A length error of s moves its subtree by s along the origin's
  // direction: the shifts' columns times that direction in camera axes.
  forward_kinematics(*model_, q_, kinematics_);
  const int first = setup_.model_error ? int(shift_cross.cols()) : 0;
  for (std::size_t i = 0; i < setup_.lengths.size(); ++i) {
    const ReportedCovarianceSetup::LengthParameter& length = setup_.lengths[i];
    const Eigen::Vector3d shift_m = T_camera_link(*model_, kinematics_, length.parent).linear() *
                                    length.direction_in_parent * setup_.link_length_std_m;
    auto column = consider_cross_.col(first + int(i));
    column.setZero();
    for (int a : length.top_shift_links)
      column.noalias() += shift_cross.middleCols<3>(3 * a) * shift_m;
  }
}

}  // namespace arttrack
