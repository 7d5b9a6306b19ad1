// Google Benchmark of the tracker's per-hypothesis building blocks on the
// project robot: forward kinematics and CPU depth rendering.
//
//   build/bench_tracker [--benchmark_filter=...]
//
// The robot is models/dual_arm.urdf (override with ARTTRACK_BENCH_URDF) at
// its documented home pose, seen by its head camera with a 45 degree
// vertical field of view.
// Targets (issue: >= 1000 renders per 33 ms image on 2 cores): forward
// kinematics <= 2 us, a render at 80x60 <= 0.1 ms.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {
namespace {

std::string urdf_path() {
  const char* path = std::getenv("ARTTRACK_BENCH_URDF");
  return path ? std::string(path) : std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm.urdf";
}

const RobotModel& robot() {
  static const RobotModel model = RobotModel::from_urdf_file(urdf_path());
  return model;
}

// The same robot with coarser primitives (16-sided cylinders, 12-meridian
// spheres): at 80x60 a 32-sided cylinder is a few pixels wide.
const RobotModel& coarse_robot() {
  static const RobotModel model = [] {
    RobotModelOptions options;
    options.cylinder_segments = 16;
    options.sphere_segments = 12;
    return RobotModel::from_urdf_file(urdf_path(), options);
  }();
  return model;
}

// The home pose documented in the header of models/dual_arm.urdf (degrees),
// then any "name=radians,..." overrides from ARTTRACK_BENCH_POSE. Joints the
// model lacks are skipped, so another URDF can be benchmarked too.
Eigen::VectorXd home_pose(const RobotModel& model) {
  const std::pair<const char*, double> home_deg[] = {
      {"head_tilt_joint", 40},    {"left_arm_joint_1", -10}, {"left_arm_joint_2", 90},
      {"left_arm_joint_3", 65},   {"left_arm_joint_4", 90},  {"left_arm_joint_5", -45},
      {"left_arm_joint_6", -35},  {"right_arm_joint_1", 10}, {"right_arm_joint_2", 90},
      {"right_arm_joint_3", -65}, {"right_arm_joint_4", 90}, {"right_arm_joint_5", 45},
      {"right_arm_joint_6", -35}};
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  const auto& names = model.joint_names();
  for (const auto& [name, deg] : home_deg) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) q[it - names.begin()] = deg * std::numbers::pi / 180;
  }
  const char* spec = std::getenv("ARTTRACK_BENCH_POSE");
  std::string rest = spec ? spec : "";
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    const std::string item = rest.substr(0, comma);
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    const size_t eq = item.find('=');
    q[model.joint_index(item.substr(0, eq))] = std::stod(item.substr(eq + 1));
  }
  return q;
}

void BM_ForwardKinematics(benchmark::State& bench) {
  const RobotModel& model = robot();
  KinematicsState state(model);
  const Eigen::VectorXd q = home_pose(model);
  for (auto _ : bench) {
    forward_kinematics(model, q, state);
    benchmark::DoNotOptimize(state.T_root_link.data());
    benchmark::ClobberMemory();
  }
  bench.counters["links"] = model.num_links();
  bench.counters["dofs"] = model.num_joints();
}
BENCHMARK(BM_ForwardKinematics);

void render_benchmark(benchmark::State& bench, const RobotModel& model) {
  const int width = int(bench.range(0)), height = int(bench.range(1));
  const CameraIntrinsics camera =
      CameraIntrinsics::from_vertical_fov(width, height, 45 * std::numbers::pi / 180);
  DepthRenderer renderer(model, camera);
  KinematicsState state(model);
  forward_kinematics(model, home_pose(model), state);
  DepthImage depth;
  PixelRect rect;
  for (auto _ : bench) {
    rect = renderer.render(state, depth);
    benchmark::DoNotOptimize(depth.depth_m.data());
    benchmark::ClobberMemory();
  }
  int covered = 0, triangles = 0;
  for (float d : depth.depth_m) covered += d > 0;
  for (int l : model.links_with_geometry()) triangles += int(model.link(l).mesh.triangles.size());
  bench.counters["robot_px"] = covered;
  bench.counters["rect_px"] = rect.area();
  bench.counters["triangles"] = triangles;
}

void BM_Render(benchmark::State& bench) { render_benchmark(bench, robot()); }
BENCHMARK(BM_Render)
    ->Args({80, 60})
    ->Args({160, 120})
    ->Args({640, 480})
    ->Unit(benchmark::kMicrosecond);

void BM_RenderCoarse(benchmark::State& bench) { render_benchmark(bench, coarse_robot()); }
BENCHMARK(BM_RenderCoarse)->Args({80, 60})->Unit(benchmark::kMicrosecond);

// A hypothesis that moves one wrist: only the links below it are drawn over
// a cached image of the rest (the coordinate particle filter's inner loop).
void BM_RenderCachedWrist(benchmark::State& bench) {
  const RobotModel& model = robot();
  const CameraIntrinsics camera =
      CameraIntrinsics::from_vertical_fov(80, 60, 45 * std::numbers::pi / 180);
  DepthRenderer renderer(model, camera);
  KinematicsState state(model);
  const Eigen::VectorXd q = home_pose(model);
  forward_kinematics(model, q, state);
  CachedRenderer cache(renderer, {model.joint_index("left_arm_joint_5")});
  cache.set_reference(state);
  DepthImage depth;
  for (auto _ : bench) {
    cache.render(state, depth);
    benchmark::DoNotOptimize(depth.depth_m.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_RenderCachedWrist)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace arttrack

BENCHMARK_MAIN();
