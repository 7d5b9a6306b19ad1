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
#include <ctime>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "../tests/dual_arm_home.h"
#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/internal/coordinate_particle_filter.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/internal/hypothesis_evaluator.h"
#include "arttrack/tracker/internal/worker_pool.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"
#include "arttrack/tracker/units.h"

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

// The dual arm's home pose (tests/dual_arm_home.h: models/scene_default.yaml,
// the pose documented in the header of models/dual_arm.urdf), then any
// "name=radians,..." overrides from ARTTRACK_BENCH_POSE. Joints the model
// lacks are skipped, so another URDF can be benchmarked too.
Eigen::VectorXd home_pose(const RobotModel& model) {
  Eigen::VectorXd q = test_support::dual_arm_home_pose(model);
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
      CameraIntrinsics::from_vertical_fov(width, height, 45 * kRadPerDeg);
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

// The same with the geometry the tracker draws: the default configuration's
// levels of detail for an 80x60 camera (docs/performance.md, "Meshes"). On
// a model of primitives it is the model itself.
void BM_RenderSimplified(benchmark::State& bench) {
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(
      int(bench.range(0)), int(bench.range(1)), 45 * kRadPerDeg);
  const TrackerConfig::Geometry geometry = default_tracker_config().geometry;
  static const RobotModel drawn =
      robot().with_simplified_meshes(geometry.error_bound_m(camera), nullptr,
                                     geometry.nearest_range_m, geometry.coarser_levels, 2);
  render_benchmark(bench, drawn);
}
BENCHMARK(BM_RenderSimplified)->Args({80, 60})->Unit(benchmark::kMicrosecond);

// A hypothesis that moves one wrist: only the links below it are drawn over
// a cached image of the rest (the coordinate particle filter's inner loop).
void BM_RenderCachedWrist(benchmark::State& bench) {
  const RobotModel& model = robot();
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 45 * kRadPerDeg);
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

// ------------------------------------------------ image update hot loop
// The particle filter of one image on the home pose: an observation of the
// robot a few degrees away (3 mm noise, a wall behind), the prior at the
// home pose (3 degrees per arm joint, 1 per head joint, 1 cm / 0.5 degree
// camera), one block per joint, hand to root (right arm, head, left arm;
// then the camera joints: the tracker's default blocks before 9e448b0,
// which leaves out joints whose bias is not estimated, the dual arm's
// head), scored by HypothesisEvaluator.
struct ImageUpdateFixture {
  const RobotModel& model = robot();
  CameraIntrinsics camera;
  DepthImage observed;
  std::vector<SamplingBlock> blocks;
  std::vector<double> prior_mean, prior_std;

  ImageUpdateFixture(int width, int height)
      : camera(CameraIntrinsics::from_vertical_fov(width, height, 45 * kRadPerDeg)) {
    constexpr double deg = kRadPerDeg;
    const Eigen::VectorXd home = home_pose(model);
    Eigen::VectorXd truth = home;
    for (int j = 0; j < model.num_joints(); ++j)
      if (!model.is_virtual_joint(j)) truth[j] += (j % 3 - 1) * 2 * deg;
    truth[model.joint_index("camera_offset_x")] = 0.005;
    KinematicsState state(model);
    forward_kinematics(model, truth, state);
    DepthRenderer renderer(model, camera);
    renderer.render(state, observed);
    std::mt19937_64 rng(3);
    std::normal_distribution<float> noise(0.f, 0.003f);
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u) {
        float& z = observed.at(u, v);
        z = z > 0 ? z + noise(rng) : 2.0f + 0.5f * float(v) / float(height);
      }
    int n_phys = 0;
    while (!model.is_virtual_joint(n_phys)) ++n_phys;
    for (int j = n_phys - 1; j >= 0; --j) blocks.push_back({model.joint_name(j), {j}});
    for (int j = n_phys; j < model.num_joints(); ++j) blocks.push_back({model.joint_name(j), {j}});
    prior_mean.assign(home.data(), home.data() + home.size());
    for (int j = 0; j < model.num_joints(); ++j) {
      const std::string& name = model.joint_name(j);
      prior_std.push_back(!model.is_virtual_joint(j) ? (name.rfind("head", 0) == 0 ? 1 : 3) * deg
                          : j < n_phys + 3           ? 0.01
                                                     : 0.5 * deg);
    }
  }
};

// One particle-filter block: the evaluation of all particles after block k
// was perturbed (args: width, height, block, particles; one worker). The
// earlier blocks run untimed; manual time = CPU time of the calling thread
// during block k (one worker: all the work, and unlike wall time it does not
// grow when other jobs share the cores).
// Block 0 is a wrist (cached: draws the hand), 6 a shoulder (cached: the
// whole arm), 7 the head tilt (full render), 9 the other wrist (cached, with
// the links around it redrawn per particle: the camera now differs between
// particles) and 16 a camera offset (full).
void BM_CpfBlock(benchmark::State& bench) {
  const ImageUpdateFixture f(int(bench.range(0)), int(bench.range(1)));
  const int timed_block = int(bench.range(2));
  DepthModelParams params;
  params.width = f.camera.width;
  params.height = f.camera.height;
  DepthLikelihood likelihood(params);
  likelihood.set_observation(f.observed);
  HypothesisEvaluator evaluator(f.model, f.blocks);
  struct Timed : LogLikelihoodEvaluator {
    HypothesisEvaluator* inner;
    int block;
    double seconds = 0;
    static double thread_cpu_s() {
      timespec t;
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
      return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
    }
    void evaluate(const ParticleBatch& batch, std::span<double> out, WorkerPool& pool) override {
      const double start = thread_cpu_s();
      inner->evaluate(batch, out, pool);
      if (batch.block == block) seconds = thread_cpu_s() - start;
    }
  } timed;
  timed.inner = &evaluator;
  timed.block = timed_block;
  CoordinateParticleFilterParams cpf_params;
  cpf_params.num_particles = int(bench.range(3));
  CoordinateParticleFilter cpf(f.model.num_joints(), f.blocks, cpf_params);
  WorkerPool pool(1);
  std::mt19937_64 rng(1);
  for (auto _ : bench) {
    evaluator.begin_run(f.camera, likelihood, f.prior_mean);
    cpf.run(f.prior_mean, f.prior_std, timed, rng, pool);
    bench.SetIterationTime(timed.seconds);
  }
  bench.SetLabel(f.blocks[timed_block].name +
                 (evaluator.renders_fully(timed_block) ? " (full)" : " (cached)"));
  bench.counters["us_per_particle"] = benchmark::Counter(
      double(cpf_params.num_particles) * double(bench.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}
BENCHMARK(BM_CpfBlock)
    ->Args({80, 60, 0, 46})
    ->Args({80, 60, 6, 46})
    ->Args({80, 60, 7, 46})
    ->Args({80, 60, 9, 46})
    ->Args({80, 60, 16, 46})
    ->Args({160, 120, 0, 19})
    ->Args({160, 120, 6, 19})
    ->Args({160, 120, 16, 19})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

// A whole image update's particle filter (args: width, height, particles,
// workers, cached): 22 blocks x particles evaluations. Real time; with one
// worker the CPU column is all the work.
void BM_CpfImage(benchmark::State& bench) {
  const ImageUpdateFixture f(int(bench.range(0)), int(bench.range(1)));
  DepthModelParams params;
  params.width = f.camera.width;
  params.height = f.camera.height;
  DepthLikelihood likelihood(params);
  likelihood.set_observation(f.observed);
  HypothesisEvaluator evaluator(
      f.model, f.blocks,
      bench.range(4) ? HypothesisEvaluator::Mode::kCached : HypothesisEvaluator::Mode::kReference);
  CoordinateParticleFilterParams cpf_params;
  cpf_params.num_particles = int(bench.range(2));
  CoordinateParticleFilter cpf(f.model.num_joints(), f.blocks, cpf_params);
  WorkerPool pool(int(bench.range(3)));
  std::mt19937_64 rng(1);
  for (auto _ : bench) {
    evaluator.begin_run(f.camera, likelihood, f.prior_mean);
    cpf.run(f.prior_mean, f.prior_std, evaluator, rng, pool);
  }
  bench.counters["evaluations"] = cpf.num_evaluations();
  bench.SetLabel(bench.range(4) ? "cached" : "reference");
}
BENCHMARK(BM_CpfImage)
    ->Args({80, 60, 46, 1, 0})
    ->Args({80, 60, 46, 1, 1})
    ->Args({80, 60, 46, 2, 1})
    ->Args({160, 120, 19, 1, 1})
    ->Args({160, 120, 19, 2, 1})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace arttrack

BENCHMARK_MAIN();
