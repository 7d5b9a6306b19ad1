// The robot as the image update draws it for a camera at the likelihood's
// resolution: the model's meshes simplified to a fraction of that camera's
// pixel (TrackerConfig::geometry, mesh_simplify.h), once per error bound and
// shared by the trackers of a process that track the same model, and a
// renderer of single configurations (the estimate's health, the searches'
// scores, the covariance's information).
//
// Setup: the model and TrackerConfig::Geometry. Workspace: the drawn model
// for the last camera, its renderer and the scratch score() draws into.
// Internal to the tracker (tracker/internal: not installed). Not
// thread-safe: the image thread's.
#pragma once

#include <memory>
#include <span>

#include <Eigen/Core>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack {

// `model` with its meshes simplified to bound_m (RobotModel::
// with_simplified_meshes; error_m: the largest error made), shared by the
// trackers of a process that track the same model at the same bound (a
// scenario's methods and runs): simplifying a maker's meshes takes about a
// second per 150 000 triangles on one thread (`threads` share the links).
// An entry lives as long as its source model. Thread-safe.
std::shared_ptr<const RobotModel> simplified_model(const std::shared_ptr<const RobotModel>& model,
                                                   double bound_m, double nearest_range_m,
                                                   int levels, double& error_m, int threads = 1);

class RenderGeometry {
 public:
  // `threads`: for the simplification (simplified_model).
  RenderGeometry(std::shared_ptr<const RobotModel> model, const TrackerConfig::Geometry& params,
                 int threads = 1);

  // Whether the renderer draws for `camera` (made by use_camera()).
  bool has_camera(const CameraIntrinsics& camera) const {
    return renderer_ != nullptr && camera_ == camera;
  }
  // Makes the renderer for `camera`, and the drawn model when the camera's
  // error bound differs from the last one. Returns true when the drawn
  // model changed: what draws it (HypothesisEvaluator) must be made again.
  bool use_camera(const CameraIntrinsics& camera);

  // After use_camera(): the drawn model, its error bound (<= 0: the model's
  // own meshes; -1 before the first camera) and the error the simplification
  // made, and the renderer.
  const RobotModel& drawn_model() const { return *drawn_; }
  double error_bound_m() const { return error_bound_m_; }
  double error_m() const { return error_m_; }
  DepthRenderer& renderer() { return *renderer_; }
  // How the drawn model is drawn (TrackerConfig::Geometry::open_parts_both_sides).
  RenderOptions render_options() const {
    RenderOptions options;
    options.open_parts_both_sides = params_.open_parts_both_sides;
    return options;
  }

  // The tempered image log-likelihood ratio of the robot at q (every DOF),
  // beta * log p(z | r(q)) / p(z | no robot) over the likelihood's
  // observation (depth_likelihood.h; beta: likelihood_exponent).
  double score(std::span<const double> q, const DepthLikelihood& likelihood, double beta);

 private:
  // Setup.
  std::shared_ptr<const RobotModel> model_;
  TrackerConfig::Geometry params_;
  int threads_ = 1;
  // Workspace.
  std::shared_ptr<const RobotModel> drawn_;
  double error_bound_m_ = -1, error_m_ = 0;
  std::unique_ptr<DepthRenderer> renderer_;
  CameraIntrinsics camera_;
  KinematicsState kinematics_;
  Eigen::VectorXd q_;
  DepthImage rendered_;
};

}  // namespace arttrack
