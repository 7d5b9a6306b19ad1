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
// A scene holds the initial (home) pose. A scenario shows its first run
// (the scenario's seed, or --seed) at the joint step nearest T, simulated
// as `arttrack run` simulates it (its motion, loads and occluders;
// run_physics.h): the way to see the links over the motion. The robot is
// the one that run simulates (a scenario's simulated_urdf and
// model_mismatch, under model_mismatch.random run 0's draw, its head error
// and camera miscalibration), and the tracker draws its nominal URDF from
// the true camera, so that their disagreement is the model error alone.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <span>
#include <string>

#include "arttrack/sim/depth_compare.h"
#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/scene_render.h"
#include "arttrack/tracker/error.h"
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

void run(const RenderArgs& args) {
  const fs::path input = args.input.empty() ? sim::default_scene_path() : fs::path(args.input);
  const fs::path out = args.out_dir;
  // Read the inputs before making the output folder: a bad one leaves none.
  const sim::SceneRender r = sim::render_scene(input, args.time_s, args.seed);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (!fs::is_directory(out)) throw InputError(out.string() + ": cannot create output folder");

  sim::write_depth_png_mm(out / "sim_depth.png", r.scene_depth);
  sim::write_depth_png_mm(out / "model_depth.png", r.model_depth);
  // One colour scale for both previews, so equal colours mean equal depths.
  double lo = 1e9, hi = 0;
  for (float z : r.scene_depth.depth_m)
    if (z > 0) lo = std::min(lo, double(z)), hi = std::max(hi, double(z));
  if (hi <= lo) lo = r.near_m, hi = r.far_m;
  sim::write_depth_preview_png(out / "sim_depth_preview.png", r.scene_depth, lo, hi);
  sim::write_depth_preview_png(out / "model_depth_preview.png", r.model_depth, lo, hi);

  const CameraIntrinsics& K = r.camera;
  std::cout
      << "scene " << r.scene_file << " (robot " << r.robot_urdf << ")\n"
      << "simulated robot " << r.simulated_urdf << ", off the tracker's: " << r.model_mismatch
      << "\n"
      << "time " << r.time_s << " s, camera " << K.width << "x" << K.height << " fx " << K.fx
      << " px, GL " << r.gl << "\n"
      << (r.follows_scenario
              ? "robot along the motion of the scenario's first run, occluders on their schedules\n"
              : "robot at home\n")
      << "wrote " << (out / "sim_depth.png").string() << ", " << (out / "model_depth.png").string()
      << ", " << (out / "sim_depth_preview.png").string() << " and "
      << (out / "model_depth_preview.png").string() << "\n";
  std::printf(
      "tracker geometry: %d triangles in the model, %d drawn (%g px of the %dx%d likelihood at "
      "%g m: at most %.2f mm; the simplifier reports %.2f mm)\n",
      r.model_triangles, r.drawn_triangles, r.max_error_px, r.likelihood_camera.width,
      r.likelihood_camera.height, r.nearest_range_m, 1e3 * r.error_bound_m,
      1e3 * r.simplifier_error_m);
  std::printf("  %s\n", r.mesh_parts.c_str());
  std::printf("  levels of detail:");
  for (std::size_t k = 1; k <= r.level_triangles.size(); ++k)
    std::printf("%s %d beyond %g m", k > 1 ? "," : "", r.level_triangles[k - 1],
                r.nearest_range_m * double(1 << k));
  std::printf("\n");
  const sim::DepthAgreement robot_only = sim::compare_depth(r.model_depth, r.robot_depth, 2e-3);
  std::cout << "tracker render vs MuJoCo robot alone: " << robot_only.summary() << "\n";
  const sim::DepthAgreement full_only = sim::compare_depth(r.full_model_depth, r.robot_depth, 2e-3);
  std::cout << "the same with the full meshes: " << full_only.summary() << "\n";
  // In the whole scene the robot may be hidden by objects; what matters there
  // is the share of the tracker's robot pixels the sensor really sees.
  const sim::DepthAgreement whole = sim::compare_depth(r.model_depth, r.scene_depth, 2e-3);
  std::printf("tracker robot pixels seen as such in the whole scene: %.2f%% (%ld of %ld)\n",
              100.0 * double(whole.within_tolerance) / double(std::max(1L, whole.pixels_a)),
              whole.within_tolerance, whole.pixels_a);
}

}  // namespace

void register_render(CLI::App& app) {
  const auto [cmd, args] =
      add_command(app, "render",
                  "Render the simulator's depth and the tracker's robot render; compare them", run);
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
  add_out_option(cmd, args->out_dir, "Output folder")->required();
}

}  // namespace arttrack::cli
