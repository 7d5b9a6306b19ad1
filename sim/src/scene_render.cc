#include "arttrack/sim/scene_render.h"

#include <algorithm>
#include <cmath>

#include "arttrack/sim/depth_camera.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

SceneRender render_scene(const fs::path& scene_or_scenario, double time_s) {
  if (!std::isfinite(time_s) || time_s < 0 || time_s > 3600)
    throw InputError("render time " + std::to_string(time_s) +
                     " s is not a number of seconds in [0, 3600]");
  SceneRender out;
  const fs::path scene_file = resolve_scene_file(scene_or_scenario);
  const SceneDescription scene = load_scene(scene_file);
  const TrackerConfig config = scene_file != scene_or_scenario
                                   ? load_scenario(scene_or_scenario).tracker
                                   : default_tracker_config();
  const auto model = build_sim_model(scene);
  Simulator simulator(model);
  const Eigen::VectorXd home = model->initial_joints;
  simulator.run_until(time_s, [&](double, Eigen::VectorXd& q) { q = home; });
  DepthCamera camera(model);
  camera.render(simulator.data(), DepthContent::kScene, out.scene_depth);
  camera.render(simulator.data(), DepthContent::kRobot, out.robot_depth);
  out.scene_file = scene_file.string();
  out.time_s = simulator.time_s();
  out.camera = camera.intrinsics();

  // The tracker's model at the simulator's true angles, looked up by name.
  RobotModelOptions options;
  options.add_virtual_camera_joints = false;
  const RobotModel robot = tracker_robot_model(scene, scene.urdf_path, options);
  const GroundTruth truth = simulator.ground_truth();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(robot.num_joints());
  for (int i = 0; i < robot.num_joints(); ++i) {
    const auto it =
        std::find(model->joint_names.begin(), model->joint_names.end(), robot.joint_name(i));
    if (it == model->joint_names.end())
      throw InputError("joint '" + robot.joint_name(i) +
                       "' of the tracker's model is missing from the simulated robot");
    q[i] = truth.q[it - model->joint_names.begin()];
  }
  KinematicsState state(robot);
  forward_kinematics(robot, q, state);
  const CameraIntrinsics likelihood_camera =
      subsampled_intrinsics(out.camera, config.depth_model.width, config.depth_model.height);
  const RobotModel drawn =
      robot.with_simplified_meshes(config.geometry.error_bound_m(likelihood_camera), nullptr,
                                   config.geometry.nearest_range_m, config.geometry.coarser_levels);
  DepthRenderer(drawn, out.camera).render(state, out.model_depth);
  out.model_triangles = robot.num_drawn_triangles();
  out.drawn_triangles = drawn.num_drawn_triangles();
  return out;
}

}  // namespace arttrack::sim
