#include "arttrack/sim/scene_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "arttrack/sim/depth_camera.h"
#include "arttrack/sim/run_physics.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/scoring.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"
#include "arttrack/tracker/units.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

// What `p` changes of the nominal robot, for people: "none", or each
// origin's length, each link's scale, the head's changed joints and the
// camera's offset.
std::string describe_model_mismatch(const UrdfPerturbation& p) {
  std::string out, origins, scales;
  char buf[160];
  auto add = [&](const std::string& part) { out += (out.empty() ? "" : "; ") + part; };
  for (const auto& [joint, m] : p.origin_extension_m)
    if (m != 0) {
      std::snprintf(buf, sizeof buf, " %s %+.1f mm", joint.c_str(), 1e3 * m);
      origins += buf;
    }
  if (!origins.empty()) add("joint origins" + origins);
  for (const auto& [link, scale] : p.link_scale)
    if (scale != 1) {
      std::snprintf(buf, sizeof buf, " %s x%.3f", link.c_str(), scale);
      scales += buf;
    }
  if (!scales.empty()) add("link scales" + scales);
  if (!p.joint_changes.empty()) {
    std::string part = "joint origins and axes changed:";
    for (const JointOriginChange& c : p.joint_changes) part += " " + c.joint;
    add(part);
  }
  const Eigen::Isometry3d& T = p.T_nominal_true_camera;
  if (!T.isApprox(Eigen::Isometry3d::Identity())) {
    std::snprintf(buf, sizeof buf, "camera %.1f mm and %.2f deg from its nominal mount",
                  1e3 * T.translation().norm(), Eigen::AngleAxisd(T.linear()).angle() * kDegPerRad);
    add(buf);
  }
  return out.empty() ? "none" : out;
}

}  // namespace

SceneRender render_scene(const fs::path& scene_or_scenario, double time_s, std::int64_t seed) {
  if (!std::isfinite(time_s) || time_s < 0 || time_s > 3600)
    throw InputError("render time " + std::to_string(time_s) +
                     " s is not a number of seconds in [0, 3600]");
  SceneRender out;
  const fs::path scene_file = resolve_scene_file(scene_or_scenario);
  std::optional<Scenario> scenario;
  if (scene_file != scene_or_scenario) scenario.emplace(load_scenario(scene_or_scenario));
  const SceneDescription scene = scenario ? scenario->scene : load_scene(scene_file);
  // The tracker configuration that decides the geometry it draws.
  const TrackerConfig config = scenario ? scenario->tracker : default_tracker_config();

  // A scenario's first run simulates its own robot (simulated_urdf,
  // model_mismatch, under model_mismatch.random run 0's draw, the head's
  // kinematic error and the camera's miscalibration), stepped as the run
  // steps it (RunPhysics: the same time step, loads and occluders).
  const SceneDescription simulated = scenario ? run_scene(*scenario) : scene;
  UrdfPerturbation perturbation;
  const std::uint64_t scenario_seed =
      scenario ? (seed >= 0 ? std::uint64_t(seed) : scenario->seed) : 0;
  if (scenario) perturbation = run_robot(*scenario, scenario_seed, 0).perturbation;
  out.model_mismatch = describe_model_mismatch(perturbation);
  const auto model = build_sim_model(simulated, perturbation);
  Simulator simulator(model);
  if (scenario) {
    RunPhysics physics(*scenario, simulator, run_trajectory(*scenario, *model, scenario_seed, 0));
    physics.advance_to(time_s);
  } else {
    const Eigen::VectorXd home = model->initial_joints;
    simulator.run_until(time_s, [&](double, Eigen::VectorXd& q) { q = home; });
  }
  DepthCamera camera(model);
  camera.render(simulator.data(), DepthContent::kScene, out.scene_depth);
  camera.render(simulator.data(), DepthContent::kRobot, out.robot_depth);
  out.scene_file = scene_file.string();
  out.robot_urdf = (scenario ? scenario->tracker_urdf() : scene.urdf_path).string();
  out.simulated_urdf = simulated.urdf_path.string();
  out.time_s = simulator.time_s();
  out.camera = camera.intrinsics();
  out.gl = camera.gl_description();
  out.follows_scenario = scenario.has_value();
  out.near_m = scene.near_m;
  out.far_m = scene.far_m;

  // The tracker's model (its nominal URDF) at the simulator's true angles,
  // looked up by name, seen from the true camera: its virtual camera joints
  // at the offset that puts its camera where the simulated one is. What
  // differs from MuJoCo's robot is then the model error alone.
  const auto robot_ptr = std::make_shared<const RobotModel>(
      tracker_robot_model(scene, scenario ? scenario->tracker_urdf() : scene.urdf_path));
  const RobotModel& robot = *robot_ptr;
  const GroundTruth truth = simulator.ground_truth();
  out.joint_names = model->joint_names;
  out.joint_angle_rad.assign(truth.q.data(), truth.q.data() + truth.q.size());
  Eigen::VectorXd angle_rad(robot.num_joints() - CameraOffset::RowsAtCompileTime);
  for (int i = 0; i < angle_rad.size(); ++i) {
    const auto it =
        std::find(model->joint_names.begin(), model->joint_names.end(), robot.joint_name(i));
    if (it == model->joint_names.end())
      throw InputError("joint '" + robot.joint_name(i) +
                       "' of the tracker's model is missing from the simulated robot");
    angle_rad[i] = truth.q[it - model->joint_names.begin()];
  }
  Eigen::VectorXd q(robot.num_joints());
  q.head(angle_rad.size()) = angle_rad;
  q.tail<CameraOffset::RowsAtCompileTime>() =
      CameraPoses(robot_ptr).offset_to(angle_rad, truth.T_world_camera);
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
