#include "arttrack/tracker/internal/end_effector_axis_search.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "arttrack/tracker/internal/end_effector_fit.h"

namespace arttrack {

EndEffectorAxisSearch::EndEffectorAxisSearch(const RobotModel& model,
                                             const std::vector<int>& fit_links, double range_m,
                                             double max_std_m)
    : model_(model),
      range_m_(range_m),
      max_var_m2_(max_std_m * max_std_m),
      shifts_m_(fit_links.size(), Eigen::Vector3d::Zero()),
      at_q_(model),
      moved_(model),
      q_(Eigen::VectorXd::Zero(model.num_joints())),
      scores_(2 * kSteps + 1, 0.0) {
  for (int fit_link : fit_links) {
    subtrees_.push_back(model.links_below(fit_link));
    others_.push_back(subtrees_.back());
    others_.back().flip();  // the rest of the robot
  }
}

std::span<const Eigen::Vector3d> EndEffectorAxisSearch::search(
    DepthRenderer& renderer, const DepthLikelihood& likelihood, std::span<const double> q,
    const std::vector<ImageInformation::RigidFit>& fits) {
  std::fill(shifts_m_.begin(), shifts_m_.end(), Eigen::Vector3d::Zero());
  if (!on()) return shifts_m_;
  for (int j = 0; j < q_.size(); ++j) q_[j] = q[std::size_t(j)];
  forward_kinematics(model_, q_, at_q_);
  const Eigen::Isometry3d& T_root_camera = at_q_.T_root_link[std::size_t(model_.camera_link())];
  const Eigen::Isometry3d T_camera_root = T_root_camera.inverse(Eigen::Isometry);
  const int W = renderer.camera().width;
  for (std::size_t f = 0; f < subtrees_.size() && f < fits.size(); ++f) {
    Eigen::Isometry3d motion;
    Eigen::Matrix3d noise_m2;
    if (!rigid_fit_motion(fits[f], max_var_m2_, motion, noise_m2)) continue;
    ++searched_;
    const Eigen::Vector3d u =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(noise_m2).eigenvectors().col(2);
    const LinkSet& subtree = subtrees_[f];
    // The subtree at the fit's motion moved by s u (camera axes), in root axes.
    auto place = [&](double s_m) {
      Eigen::Isometry3d M = motion;
      M.pretranslate(s_m * u);
      const Eigen::Isometry3d T = T_root_camera * M * T_camera_root;
      for (int l = 0; l < model_.num_links(); ++l)
        if (subtree[std::size_t(l)])
          moved_.T_root_link[std::size_t(l)] = T * at_q_.T_root_link[std::size_t(l)];
    };
    moved_.T_root_link = at_q_.T_root_link;  // sizes kept: no allocation
    renderer.render_links(at_q_, others_[f], statics_);
    work_ = statics_;
    // A translation moves each point's image along a line, monotonically:
    // every grid point's pixels lie in the union of the ends' rectangles.
    PixelRect rect;
    for (double end_m : {-range_m_, range_m_}) {
      place(end_m);
      rect = rect.united(renderer.draw_links(moved_, subtree, work_));
      std::copy(statics_.depth_m.begin(), statics_.depth_m.end(), work_.depth_m.begin());
    }
    if (rect.empty()) continue;
    const double step_m = range_m_ / kSteps;
    for (int k = -kSteps; k <= kSteps; ++k) {
      place(k * step_m);
      renderer.draw_links(moved_, subtree, work_);
      const float* origin = work_.depth_m.data() + std::size_t(rect.v0) * W + rect.u0;
      scores_[std::size_t(k + kSteps)] = likelihood.log_ratio(origin, W, rect);
      for (int v = rect.v0; v < rect.v1; ++v) {
        const std::size_t row = std::size_t(v) * W;
        std::copy(statics_.depth_m.begin() + row + rect.u0,
                  statics_.depth_m.begin() + row + rect.u1, work_.depth_m.begin() + row + rect.u0);
      }
    }
    const int best = int(std::max_element(scores_.begin(), scores_.end()) - scores_.begin());
    if (!(scores_[std::size_t(best)] - scores_[kSteps] > kMinGainNats)) continue;
    // The run of grid points tied with the best, around it: its middle.
    int first = best, last = best;
    const double tie = scores_[std::size_t(best)] - kPlateauNats;
    while (first > 0 && scores_[std::size_t(first - 1)] >= tie) --first;
    while (last < 2 * kSteps && scores_[std::size_t(last + 1)] >= tie) ++last;
    shifts_m_[f] = (0.5 * (first + last) - kSteps) * step_m * u;
    ++accepted_;
  }
  return shifts_m_;
}

}  // namespace arttrack
