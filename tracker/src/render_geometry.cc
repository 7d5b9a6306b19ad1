#include "arttrack/tracker/internal/render_geometry.h"

#include <mutex>
#include <vector>

namespace arttrack {

std::shared_ptr<const RobotModel> simplified_model(const std::shared_ptr<const RobotModel>& model,
                                                   double bound_m, double nearest_range_m,
                                                   int levels, double& error_m, int threads) {
  struct Entry {
    std::weak_ptr<const RobotModel> source;
    double bound_m, nearest_range_m;
    int levels;
    double error_m;
    std::shared_ptr<const RobotModel> simplified;
  };
  static std::mutex mutex;
  static std::vector<Entry> cache;
  std::lock_guard lock(mutex);
  std::erase_if(cache, [](const Entry& e) { return e.source.expired(); });
  for (const Entry& e : cache) {
    if (e.source.lock() == model && e.bound_m == bound_m && e.nearest_range_m == nearest_range_m &&
        e.levels == levels) {
      error_m = e.error_m;
      return e.simplified;
    }
  }
  auto simplified = std::make_shared<const RobotModel>(
      model->with_simplified_meshes(bound_m, &error_m, nearest_range_m, levels, threads));
  cache.push_back({model, bound_m, nearest_range_m, levels, error_m, simplified});
  return simplified;
}

RenderGeometry::RenderGeometry(std::shared_ptr<const RobotModel> model,
                               const TrackerConfig::Geometry& params, int threads)
    : model_(std::move(model)),
      params_(params),
      threads_(threads),
      kinematics_(*model_),
      q_(Eigen::VectorXd::Zero(model_->num_joints())) {}

bool RenderGeometry::use_camera(const CameraIntrinsics& camera) {
  camera_ = camera;
  const double bound_m = params_.error_bound_m(camera);
  const bool changed = !drawn_ || bound_m != error_bound_m_;
  if (changed) {
    error_bound_m_ = bound_m;
    error_m_ = 0;
    drawn_ = bound_m > 0 ? simplified_model(model_, bound_m, params_.nearest_range_m,
                                            params_.coarser_levels, error_m_, threads_)
                         : model_;
  }
  renderer_ = std::make_unique<DepthRenderer>(*drawn_, camera, render_options());
  return changed;
}

double RenderGeometry::score(std::span<const double> q, const DepthLikelihood& likelihood,
                             double beta) {
  for (int j = 0; j < q_.size(); ++j) q_[j] = q[j];
  forward_kinematics(*model_, q_, kinematics_);
  renderer_->render(kinematics_, rendered_);
  return beta * likelihood.log_ratio(rendered_);
}

}  // namespace arttrack
