// arttrack render [SCENE_OR_SCENARIO.yaml] [--time T] --out DIR
//
// Simulates to time T, then writes
//   DIR/sim_depth.png    MuJoCo's depth of the whole scene,
//   DIR/model_depth.png  the tracker's own render of the robot at the true
//                        state from the true camera, with the geometry the
//                        tracker draws (its meshes simplified for the
//                        likelihood's resolution: TrackerConfig::geometry,
//                        from the scenario's tracker configuration, or the
//                        default one for a scene),
// (16-bit PNG, millimetres, 0 = no return) and a false-colour preview of
// each (sim_depth_preview.png, model_depth_preview.png), and prints the
// triangles of the model and of what the tracker draws, and how well the
// tracker's render, with the full meshes and with the drawn ones, agrees
// with MuJoCo's render of the robot alone.
//
// A scene holds the initial (home) pose. A scenario's robot follows the
// motion of its first run (the scenario's seed, or --seed) and its
// occluders their schedules, as `arttrack run` drives them: the way to see
// the links over the motion. (The scene's nominal robot; a scenario's
// simulated_urdf, miscalibration and loads are not applied.)
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <span>
#include <string>

#include "arttrack/sim/depth_camera.h"
#include "arttrack/sim/depth_compare.h"
#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;

// Upper bound on --time: an hour of simulated time (minutes of computing).
constexpr double kMaxRenderTimeS = 3600;

struct RenderArgs {
  std::string input;
  double time_s = 0;
  long long seed = -1;  // -1: the scenario's
  std::string out_dir;
};

// The tracker's joint vector for the simulator's true state: every tracker
// DOF looked up by name in MuJoCo (virtual camera joints stay 0).
Eigen::VectorXd tracker_joints(const RobotModel& robot, const sim::Simulator& sim) {
  const mjModel* m = sim.model().mj.get();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(robot.num_joints());
  for (int i = 0; i < robot.num_joints(); ++i) {
    if (robot.is_virtual_joint(i)) continue;
    const int j = mj_name2id(m, mjOBJ_JOINT, robot.joint_name(i).c_str());
    if (j < 0)
      throw InputError("joint '" + robot.joint_name(i) + "' of the tracker's model is missing " +
                       "from the simulated robot");
    q[i] = sim.data()->qpos[m->jnt_qposadr[j]];
  }
  return q;
}

void run(const RenderArgs& args) {
  const fs::path input = args.input.empty() ? sim::default_scene_path() : fs::path(args.input);
  const fs::path scene_file = sim::resolve_scene_file(input);
  const sim::SceneDescription scene = sim::load_scene(scene_file);
  std::optional<sim::Scenario> scenario;
  if (scene_file != input) scenario.emplace(sim::load_scenario(input));
  // The tracker configuration that decides the geometry it draws.
  const TrackerConfig config = scenario ? scenario->tracker : default_tracker_config();
  const fs::path out = args.out_dir;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (!fs::is_directory(out)) throw InputError(out.string() + ": cannot create output folder");

  const auto model = sim::build_sim_model(scene);
  sim::Simulator simulator(model);
  if (scenario) {
    const std::uint64_t seed = args.seed >= 0 ? std::uint64_t(args.seed) : scenario->seed;
    const sim::JointTrajectory motion = sim::run_trajectory(*scenario, *model, seed, 0);
    simulator.run_until(args.time_s, [&](double t, Eigen::VectorXd& q) {
      motion.position(t, std::span<double>(q.data(), std::size_t(q.size())));
    });
    for (const sim::OccluderSchedule& o : scenario->occluder_schedules)
      simulator.set_occluder_pose(o.occluder, o.pose_at(simulator.time_s()));
  } else {
    const Eigen::VectorXd home = model->initial_joints;
    simulator.run_until(args.time_s, [&](double, Eigen::VectorXd& q) { q = home; });
  }

  sim::DepthCamera camera(model);
  DepthImage sim_depth, sim_robot_depth;
  camera.render(simulator.data(), sim::DepthContent::kScene, sim_depth);
  camera.render(simulator.data(), sim::DepthContent::kRobot, sim_robot_depth);

  // The tracker's model, from the same URDF and camera link.
  RobotModelOptions options;
  options.add_virtual_camera_joints = false;
  const RobotModel robot = sim::tracker_robot_model(scene, scene.urdf_path, options);
  KinematicsState state(robot);
  forward_kinematics(robot, tracker_joints(robot, simulator), state);
  // What the tracker draws: the meshes simplified for the likelihood's camera.
  const CameraIntrinsics likelihood_camera = subsampled_intrinsics(
      camera.intrinsics(), config.depth_model.width, config.depth_model.height);
  const double bound_m = config.geometry.error_bound_m(likelihood_camera);
  double simplifier_error_m = 0;
  const RobotModel drawn =
      robot.with_simplified_meshes(bound_m, &simplifier_error_m, config.geometry.nearest_range_m,
                                   config.geometry.coarser_levels);
  DepthImage model_depth, full_depth;
  DepthRenderer(drawn, camera.intrinsics()).render(state, model_depth);
  DepthRenderer(robot, camera.intrinsics()).render(state, full_depth);

  sim::write_depth_png_mm(out / "sim_depth.png", sim_depth);
  sim::write_depth_png_mm(out / "model_depth.png", model_depth);
  // One colour scale for both previews, so equal colours mean equal depths.
  double lo = 1e9, hi = 0;
  for (float z : sim_depth.depth_m)
    if (z > 0) lo = std::min(lo, double(z)), hi = std::max(hi, double(z));
  if (hi <= lo) lo = scene.near_m, hi = scene.far_m;
  sim::write_depth_preview_png(out / "sim_depth_preview.png", sim_depth, lo, hi);
  sim::write_depth_preview_png(out / "model_depth_preview.png", model_depth, lo, hi);

  const CameraIntrinsics& K = camera.intrinsics();
  std::cout
      << "scene " << scene.source << " (robot " << scene.urdf_path.string() << ")\n"
      << "time " << simulator.time_s() << " s, camera " << K.width << "x" << K.height << " fx "
      << K.fx << " px, GL " << camera.gl_description() << "\n"
      << (scenario
              ? "robot along the motion of the scenario's first run, occluders on their schedules\n"
              : "robot at home\n")
      << "wrote " << (out / "sim_depth.png").string() << ", " << (out / "model_depth.png").string()
      << ", " << (out / "sim_depth_preview.png").string() << " and "
      << (out / "model_depth_preview.png").string() << "\n";
  std::printf(
      "tracker geometry: %d triangles in the model, %d drawn (%g px of the %dx%d likelihood at "
      "%g m: at most %.2f mm; the simplifier reports %.2f mm)\n",
      robot.num_drawn_triangles(), drawn.num_drawn_triangles(), config.geometry.max_error_px,
      likelihood_camera.width, likelihood_camera.height, config.geometry.nearest_range_m,
      1e3 * bound_m, 1e3 * simplifier_error_m);
  std::printf("  levels of detail:");
  for (int k = 1; k <= config.geometry.coarser_levels; ++k)
    std::printf("%s %d beyond %g m", k > 1 ? "," : "", drawn.num_drawn_triangles(k),
                config.geometry.nearest_range_m * double(1 << k));
  std::printf("\n");
  const sim::DepthAgreement robot_only = sim::compare_depth(model_depth, sim_robot_depth, 2e-3);
  std::cout << "tracker render vs MuJoCo robot alone: " << robot_only.summary() << "\n";
  const sim::DepthAgreement full_only = sim::compare_depth(full_depth, sim_robot_depth, 2e-3);
  std::cout << "the same with the full meshes: " << full_only.summary() << "\n";
  // In the whole scene the robot may be hidden by objects; what matters there
  // is the share of the tracker's robot pixels the sensor really sees.
  const sim::DepthAgreement whole = sim::compare_depth(model_depth, sim_depth, 2e-3);
  std::printf("tracker robot pixels seen as such in the whole scene: %.2f%% (%ld of %ld)\n",
              100.0 * double(whole.within_tolerance) / double(std::max(1L, whole.pixels_a)),
              whole.within_tolerance, whole.pixels_a);
}

}  // namespace

void register_render(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render the simulator's depth and the tracker's robot render; compare them");
  cmd->add_option("scene", args->input,
                  "Scene or scenario YAML (default: models/scene_default.yaml)");
  add_seed_option(cmd, args->seed,
                  "Scenario seed, as for arttrack run: a scenario's robot follows its first run");
  cmd->add_option("--time", args->time_s,
                  "Simulated time before rendering, seconds (a scenario's robot follows its "
                  "motion, a scene's holds the home pose), at most " +
                      std::to_string(int(kMaxRenderTimeS)) + " (default 0)")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            char* end = nullptr;
            const double t = std::strtod(s.c_str(), &end);
            if (!s.empty() && *end == 0 && std::isfinite(t) && t >= 0 && t <= kMaxRenderTimeS)
              return "";
            return s + " is not a number of seconds in [0, " +
                   std::to_string(int(kMaxRenderTimeS)) + "]";
          },
          "SECONDS"));
  cmd->add_option("--out", args->out_dir, "Output folder")->required()->check(non_empty_name());
  cmd->callback([args] { run(*args); });
}

}  // namespace arttrack::cli
