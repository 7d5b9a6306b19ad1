#include "health_check.h"

#include <algorithm>
#include <limits>

namespace arttrack {

HealthCheck::HealthCheck(const RobotModel& model, int num_physical,
                         const TrackerConfig::Health& params, double max_range_m)
    : model_(model),
      params_(params),
      max_range_m_(float(max_range_m)),
      q_(Eigen::VectorXd::Zero(model.num_joints())),
      kinematics_(model) {
  // Kinematic chains: physical DOFs grouped by their top-most physical
  // ancestor DOF (for the dual-arm robot: head, left arm, right arm).
  std::vector<int> chain_root(static_cast<std::size_t>(num_physical));
  for (int j = 0; j < num_physical; ++j) {
    int root = j;
    for (int l = model.link(model.joint_child_link(j)).parent; l >= 0; l = model.link(l).parent) {
      const int d = model.link(l).dof;
      if (d >= 0 && !model.is_virtual_joint(d)) root = d;
    }
    chain_root[std::size_t(j)] = root;
  }
  for (int j = 0; j < num_physical; ++j) {
    if (chain_root[std::size_t(j)] != j) continue;
    std::vector<int> members;
    for (int k = 0; k < num_physical; ++k)
      if (chain_root[std::size_t(k)] == j) members.push_back(k);
    chains_.push_back(std::move(members));
    chain_links_.push_back(model.links_moved_by(j));
    std::vector<std::pair<int, LinkSet>> parts;
    for (int k : chains_.back())
      if (k != j) parts.emplace_back(k, model.links_moved_by(k));
    parts_.push_back(std::move(parts));
    chain_names_.push_back(model.joint_name(j));
    unconfirmed_images_.push_back(0);
    chain_poor_.push_back(0);
    explained_depth_m_.emplace_back();
  }
}

TrackingHealth HealthCheck::initial_health() const {
  TrackingHealth health;
  for (const std::string& name : chain_names_) health.chains.push_back({name});
  health.whole.name = "all";
  return health;
}

bool HealthCheck::any_unconfirmed() const {
  return std::any_of(unconfirmed_images_.begin(), unconfirmed_images_.end(),
                     [](int u) { return u > 0; });
}

void HealthCheck::confirming_search_ran() {
  ++failed_confirmations_;  // until no chain is unconfirmed
  std::fill(unconfirmed_images_.begin(), unconfirmed_images_.end(), 0);
}

void HealthCheck::reacquisition_ran() {
  poor_images_ = 0;
  ++failed_reacquisitions_;  // until the health check finds a good image
}

void HealthCheck::set_configuration(std::span<const double> q) {
  for (Eigen::Index j = 0; j < q_.size(); ++j) q_[j] = q[std::size_t(j)];
  forward_kinematics(model_, q_, kinematics_);
}

void HealthCheck::assess(const DepthImage& observed, ChainHealth& out) const {
  int rendered = 0, explained = 0, contradicted = 0;
  for (std::size_t i = 0; i < image_.depth_m.size(); ++i) {
    const float r = image_.depth_m[i], z = observed.depth_m[i];
    if (!(r > 0) || !(z > 0) || !(z <= max_range_m_)) continue;
    ++rendered;
    if (explains(r, z)) ++explained;
    if (z > r + params_.contradicted_m) ++contradicted;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const bool verdict = rendered >= params_.min_pixels;
  out.rendered_pixels = rendered;
  out.explained_fraction = verdict ? double(explained) / rendered : nan;
  out.contradicted_fraction = verdict ? double(contradicted) / rendered : nan;
}

void HealthCheck::assess_parts(std::size_t c, const DepthImage& observed, DepthRenderer& renderer,
                               ChainHealth& out) {
  out.weakest_part_joint = -1;
  out.weakest_part_explained_fraction = std::numeric_limits<double>::quiet_NaN();
  // A part's visible pixels are a subset of its chain's rendered ones: with
  // fewer than min_pixels of those (an arm out of view) no part can have a
  // verdict, and its renders are skipped.
  if (out.rendered_pixels < params_.min_pixels) {
    out.unconfirmed = false;
    return;
  }
  for (const auto& [dof, links] : parts_[c]) {
    renderer.render_links(kinematics_, links, image_);
    int visible = 0, explained = 0;
    for (std::size_t i = 0; i < image_.depth_m.size(); ++i) {
      const float r = image_.depth_m[i], z = observed.depth_m[i];
      if (!(r > 0) || !(z > 0) || !(z <= max_range_m_)) continue;
      if (full_image_.depth_m[i] < r - 1e-4f) continue;  // behind another link
      if (z < r - params_.occluder_gap_m) continue;      // behind an occluder
      ++visible;
      if (explains(r, z)) ++explained;
    }
    if (visible < params_.min_pixels) continue;
    const double fraction = double(explained) / visible;
    if (out.weakest_part_joint < 0 || fraction < out.weakest_part_explained_fraction) {
      out.weakest_part_joint = dof;
      out.weakest_part_explained_fraction = fraction;
    }
  }
  out.unconfirmed = out.weakest_part_explained_fraction < params_.unconfirmed_explained_fraction;
}

void HealthCheck::update(std::span<const double> q, const DepthImage& observed, double stamp_s,
                         DepthRenderer& renderer, TrackingHealth& health) {
  const TrackerConfig::Health& h = params_;
  set_configuration(q);
  renderer.render(kinematics_, image_);
  assess(observed, health.whole);
  std::swap(full_image_, image_);  // render_links() below overwrites image_
  bool poor = health.whole.contradicted_fraction > h.lost_contradicted_fraction;
  int kept_pixels = 0, abandoned_pixels = 0;
  for (std::size_t c = 0; c < chains_.size(); ++c) {
    renderer.render_links(kinematics_, chain_links_[c], image_);
    ChainHealth& chain = health.chains[c];
    assess(observed, chain);
    // ChainHealth: the pixels this chain explained at its last good image,
    // where the image still shows the same depth, but the render does not.
    std::vector<float>& kept = explained_depth_m_[c];
    int kept_count = 0, abandoned = 0;
    if (kept.size() != image_.depth_m.size()) kept.assign(image_.depth_m.size(), 0.0f);
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (!(kept[i] > 0)) continue;
      ++kept_count;
      const float z = observed.depth_m[i], r = image_.depth_m[i];
      if (!explains(kept[i], z)) continue;  // the scene moved
      if (!explains(r, z)) ++abandoned;
    }
    chain.abandoned_fraction = kept_count >= h.min_pixels
                                   ? double(abandoned) / kept_count
                                   : std::numeric_limits<double>::quiet_NaN();
    if (kept_count >= h.min_pixels) {
      kept_pixels += kept_count;
      abandoned_pixels += abandoned;
    }
    chain_poor_[c] = chain.contradicted_fraction > h.lost_contradicted_fraction ||
                     chain.abandoned_fraction > h.lost_abandoned_fraction;
    poor = poor || chain_poor_[c];
    if (!chain_poor_[c]) {  // else keep the evidence of its last good image
      for (std::size_t i = 0; i < kept.size(); ++i) {
        const float r = image_.depth_m[i], z = observed.depth_m[i];
        kept[i] = z <= max_range_m_ && explains(r, z) ? z : 0.0f;
      }
    }
    assess_parts(c, observed, renderer, chain);
    unconfirmed_images_[c] = chain.unconfirmed ? unconfirmed_images_[c] + 1 : 0;
  }
  if (!any_unconfirmed()) failed_confirmations_ = 0;
  health.whole.abandoned_fraction = kept_pixels > 0 ? double(abandoned_pixels) / kept_pixels
                                                    : std::numeric_limits<double>::quiet_NaN();
  poor_images_ = poor ? poor_images_ + 1 : 0;
  if (!poor) failed_reacquisitions_ = 0;
  health.state = poor_images_ >= h.lost_after_images ? TrackingHealth::State::kLost
                                                     : TrackingHealth::State::kTracking;
  health.image_stamp_s = stamp_s;
}

bool HealthCheck::supports_chain(std::span<const double> q, std::size_t c,
                                 const DepthImage& observed, DepthRenderer& renderer,
                                 double weakest_before) {
  set_configuration(q);
  renderer.render(kinematics_, full_image_);
  renderer.render_links(kinematics_, chain_links_[c], image_);
  ChainHealth chain;
  assess(observed, chain);
  assess_parts(c, observed, renderer, chain);
  return chain.weakest_part_joint >= 0 &&
         (!chain.unconfirmed || chain.weakest_part_explained_fraction > weakest_before);
}

}  // namespace arttrack
