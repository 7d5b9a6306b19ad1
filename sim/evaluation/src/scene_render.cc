#include "arttrack/sim/scene_render.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "arttrack/sim/depth_camera.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

SceneRender render_scene(const fs::path& scene_or_scenario, double time_s, std::int64_t seed) {
  if (!std::isfinite(time_s) || time_s < 0 || time_s > 3600)
    throw InputError("render time " + std::to_string(time_s) +
                     " s is not a number of seconds in [0, 3600]");
  SceneRender out;
  const fs::path scene_file = resolve_scene_file(scene_or_scenario);
  const SceneDescription scene = load_scene(scene_file);
  std::optional<Scenario> scenario;
  if (scene_file != scene_or_scenario) scenario.emplace(load_scenario(scene_or_scenario));
  // The tracker configuration that decides the geometry it draws.
  const TrackerConfig config = scenario ? scenario->tracker : default_tracker_config();

  const auto model = build_sim_model(scene);
  Simulator simulator(model);
  if (scenario) {
    const JointTrajectory motion =
        run_trajectory(*scenario, *model, seed >= 0 ? std::uint64_t(seed) : scenario->seed, 0);
    simulator.run_until(time_s, [&](double t, Eigen::VectorXd& q) {
      motion.position(t, std::span<double>(q.data(), std::size_t(q.size())));
    });
    for (const OccluderSchedule& o : scenario->occluder_schedules)
      simulator.set_occluder_pose(o.occluder, o.pose_at(simulator.time_s()));
  } else {
    const Eigen::VectorXd home = model->initial_joints;
    simulator.run_until(time_s, [&](double, Eigen::VectorXd& q) { q = home; });
  }
  DepthCamera camera(model);
  camera.render(simulator.data(), DepthContent::kScene, out.scene_depth);
  camera.render(simulator.data(), DepthContent::kRobot, out.robot_depth);
  out.scene_file = scene_file.string();
  out.robot_urdf = scene.urdf_path.string();
  out.time_s = simulator.time_s();
  out.camera = camera.intrinsics();
  out.gl = camera.gl_description();
  out.follows_scenario = scenario.has_value();
  out.near_m = scene.near_m;
  out.far_m = scene.far_m;

  // The tracker's model, from the same URDF and camera link, at the
  // simulator's true angles looked up by name (no virtual camera joints).
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
  // What the tracker draws: the meshes simplified for the likelihood's camera.
  out.likelihood_camera =
      subsampled_intrinsics(out.camera, config.depth_model.width, config.depth_model.height);
  out.max_error_px = config.geometry.max_error_px;
  out.nearest_range_m = config.geometry.nearest_range_m;
  out.error_bound_m = config.geometry.error_bound_m(out.likelihood_camera);
  const RobotModel drawn =
      robot.with_simplified_meshes(out.error_bound_m, &out.simplifier_error_m,
                                   config.geometry.nearest_range_m, config.geometry.coarser_levels);
  DepthRenderer(drawn, out.camera).render(state, out.model_depth);
  DepthRenderer(robot, out.camera).render(state, out.full_model_depth);
  out.model_triangles = robot.num_drawn_triangles();
  out.mesh_parts = describe_mesh_parts(robot);
  out.drawn_triangles = drawn.num_drawn_triangles();
  for (int k = 1; k <= config.geometry.coarser_levels; ++k)
    out.level_triangles.push_back(drawn.num_drawn_triangles(k));
  return out;
}

}  // namespace arttrack::sim
