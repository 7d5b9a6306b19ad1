// Simulator benchmarks on the default scene (models/scene_default.yaml, or
// the scene ARTTRACK_BENCH_SCENE names):
// one depth frame of the whole scene or the robot alone at 640x480 and
// 160x120, and one physics step with ground truth.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "arttrack/sim/depth_camera.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/simulator.h"

namespace arttrack::sim {
namespace {

// ARTTRACK_BENCH_SCENE names another scene (e.g. models/scene_sculpted.yaml).
const std::shared_ptr<const SimModel>& default_model() {
  static const auto model = [] {
    const char* scene = std::getenv("ARTTRACK_BENCH_SCENE");
    return build_sim_model(load_scene(scene ? std::filesystem::path(scene)
                                            : std::filesystem::path(ARTTRACK_SOURCE_DIR) /
                                                  "models/scene_default.yaml"));
  }();
  return model;
}

// Args: width, height, content (0 = whole scene, 1 = robot alone).
void BM_DepthFrame(benchmark::State& state) {
  const auto& model = default_model();
  Simulator sim(model);
  DepthCamera camera(model, int(state.range(0)), int(state.range(1)));
  const DepthContent content = state.range(2) ? DepthContent::kRobot : DepthContent::kScene;
  DepthImage depth;
  camera.render(sim.data(), content, depth);  // sizes the output once
  for (auto _ : state) {
    camera.render(sim.data(), content, depth);
    benchmark::DoNotOptimize(depth.depth_m.data());
  }
  state.SetLabel(camera.gl_description());
}
BENCHMARK(BM_DepthFrame)
    ->ArgNames({"w", "h", "robot_only"})
    ->Args({640, 480, 0})
    ->Args({160, 120, 0})
    ->Args({640, 480, 1})
    ->Args({160, 120, 1})
    ->Unit(benchmark::kMillisecond);

void BM_PhysicsStepWithGroundTruth(benchmark::State& state) {
  Simulator sim(default_model());
  GroundTruth truth;
  for (auto _ : state) {
    sim.step();
    sim.ground_truth(truth);
    benchmark::DoNotOptimize(truth.q.data());
  }
}
BENCHMARK(BM_PhysicsStepWithGroundTruth)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace arttrack::sim

BENCHMARK_MAIN();
