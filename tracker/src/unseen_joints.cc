#include "arttrack/tracker/internal/unseen_joints.h"

#include <string>
#include <utility>

#include "arttrack/tracker/error.h"

namespace arttrack {

UnseenJoints::UnseenJoints(const TrackerSetup& setup, std::vector<int> state_dofs)
    : on_(setup.config.method == TrackingMethod::kFullFusion && setup.config.keep_unseen_prior),
      below_pixels_(setup.config.unseen_below_pixels),
      nearer_m_(float(setup.config.health.explained_m)),
      model_(setup.model.get()),
      state_dofs_(std::move(state_dofs)),
      kinematics_(*setup.model),
      q_(Eigen::VectorXd::Zero(setup.n)),
      prior_(std::size_t(setup.n)),
      one_link_(std::size_t(setup.model->num_links()), false),
      link_pixels_(std::size_t(setup.model->num_links()), 0),
      link_at_edge_(std::size_t(setup.model->num_links()), 0),
      unseen_(state_dofs_.size(), 0) {
  for (int dof : state_dofs_) state_links_.push_back(links_affecting_depth(*model_, {dof}));
}

int UnseenJoints::find(const JointBelief& prior, DepthRenderer& renderer,
                       const DepthImage& observed) {
  const CameraIntrinsics& camera = renderer.camera();
  if (observed.width != camera.width || observed.height != camera.height)
    throw InputError("unseen joints: an image of " + std::to_string(observed.width) + "x" +
                     std::to_string(observed.height) + " for a camera of " +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height));
  for (int j = 0; j < q_.size(); ++j) {
    q_[j] = prior.mean_a[std::size_t(j)];
    prior_[std::size_t(j)] = prior.joint(j);
  }
  forward_kinematics(*model_, q_, kinematics_);
  // Each link alone, each pixel against the image: a link behind another
  // of the robot's links, an occluder or the view's edge is not seen there.
  for (int l : model_->links_with_geometry()) {
    one_link_[std::size_t(l)] = true;
    const PixelRect rect = renderer.render_links(kinematics_, one_link_, link_image_);
    one_link_[std::size_t(l)] = false;
    count_seen(rect, observed, link_pixels_[std::size_t(l)], link_at_edge_[std::size_t(l)]);
  }
  int count = 0;
  for (std::size_t i = 0; i < state_dofs_.size(); ++i) {
    int seen = 0;
    bool at_edge = false;
    for (int l : model_->links_with_geometry()) {
      if (!state_links_[i][std::size_t(l)]) continue;
      seen += link_pixels_[std::size_t(l)];
      at_edge = at_edge || link_at_edge_[std::size_t(l)];
    }
    // A chain small in the image but wholly in view, and in front of
    // whatever the image shows there, is seen.
    unseen_[i] = seen == 0 || (seen < below_pixels_ && at_edge);
    count += unseen_[i];
  }
  return count;
}

void UnseenJoints::count_seen(const PixelRect& rect, const DepthImage& observed, int& seen,
                              char& at_edge) const {
  const int w = link_image_.width, h = link_image_.height;
  seen = 0;
  at_edge = false;
  for (int v = rect.v0; v < rect.v1; ++v) {
    const float* row = link_image_.depth_m.data() + std::size_t(v) * w;
    const float* z = observed.depth_m.data() + std::size_t(v) * w;
    for (int u = rect.u0; u < rect.u1; ++u) {
      if (!(row[u] > 0.f) || !(z[u] > 0.f)) continue;  // no return: the image says nothing
      if (z[u] < row[u] - nearer_m_) {                 // behind a nearer surface
        at_edge = true;
        continue;
      }
      ++seen;
      at_edge = at_edge || u == 0 || v == 0 || u == w - 1 || v == h - 1;
    }
  }
}

int UnseenJoints::keep_priors(std::span<const int> pixels_per_state, JointBelief& belief) const {
  int moved = 0;
  for (std::size_t i = 0; i < state_dofs_.size(); ++i) {
    if (!unseen_[i] || (i < pixels_per_state.size() && pixels_per_state[i] > 0)) continue;
    const int dof = state_dofs_[i];
    const AngleBiasGaussian& g = prior_[std::size_t(dof)];
    moved += belief.mean_a[std::size_t(dof)] != g.mean_a;
    belief.set_joint(dof, g);
  }
  return moved;
}

}  // namespace arttrack
