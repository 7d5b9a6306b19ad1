// Speed of the estimation building blocks: the joint Kalman bank (one 1 kHz
// step, and re-filtering 100 ms after a delayed image), one depth likelihood
// evaluation, the coordinate particle filter's own overhead, and the link
// shifts learned over poses (one image's sum and solve).
//   ./bench_filters [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "arttrack/tracker/internal/coordinate_particle_filter.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/learned_link_shifts.h"
#include "arttrack/tracker/internal/worker_pool.h"

namespace arttrack {
namespace {

// Two 7-DoF arms, a 2-DoF head, 6 more (torso, grippers): 22 encoder joints,
// plus the 6 virtual camera joints.
JointFilterModel robot_bank() {
  std::vector<std::string> joints, cams;
  for (int j = 0; j < 22; ++j) joints.push_back("joint_" + std::to_string(j));
  for (const char* c : {"cam_x", "cam_y", "cam_z", "cam_roll", "cam_pitch", "cam_yaw"}) {
    cams.push_back(c);
  }
  return JointFilterModel(joints, std::vector<JointFilterParams>(22), cams,
                          std::vector<VirtualJointParams>(6));
}

void BM_JointFilterStep(benchmark::State& state) {
  const JointFilterModel model = robot_bank();
  std::vector<double> q(22);
  for (int j = 0; j < 22; ++j) q[j] = 0.1 * j;
  JointBelief belief = initial_joint_belief(model, q);
  int i = 0;
  for (auto _ : state) {
    q[i % 22] += 1e-4;  // readings change
    filter_joints(model, 1e-3, q, belief);
    benchmark::DoNotOptimize(belief.mean_a.data());
    ++i;
  }
  state.SetLabel("22 encoder + 6 virtual joints, predict+update");
}
BENCHMARK(BM_JointFilterStep);

// After a delayed image: re-filter the 100 buffered readings of 100 ms at 1 kHz.
void BM_JointRefilter100(benchmark::State& state) {
  const JointFilterModel model = robot_bank();
  std::vector<std::vector<double>> readings(100, std::vector<double>(22));
  for (int k = 0; k < 100; ++k) {
    for (int j = 0; j < 22; ++j) readings[k][j] = 0.1 * j + 0.3 * std::sin(0.01 * k + j);
  }
  const JointBelief start = initial_joint_belief(model, readings[0]);
  JointBelief belief = start;
  for (auto _ : state) {
    belief = start;  // copy of 5 x 28 doubles into existing storage
    for (int k = 0; k < 100; ++k) filter_joints(model, 1e-3, readings[k], belief);
    benchmark::DoNotOptimize(belief.mean_a.data());
  }
  state.SetLabel("100 steps x 28 joints");
}
BENCHMARK(BM_JointRefilter100);

// A plausible scene: a wall 2-3 m away, the robot covering `coverage` of the
// image at about 1 m; the hypothesis matches the observation on most covered
// pixels to within centimetres, some are occluded (observed 30 cm in
// front), some are background (the hypothesis is off there), 3% of the
// observed pixels have no return.
struct Scene {
  DepthImage observed, rendered;
  int covered = 0;
};

Scene make_scene(int w, int h, double coverage, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u01(0.f, 1.f), wall(2.f, 3.f);
  std::normal_distribution<float> near(0.f, 0.01f);
  Scene s{DepthImage(w, h), DepthImage(w, h, 0.f)};
  // The robot: a centred blob of the requested area.
  const double radius = std::sqrt(coverage * w * h / M_PI);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const double du = u + 0.5 - w / 2.0, dv = v + 0.5 - h / 2.0;
      const bool robot = du * du + dv * dv < radius * radius;
      float z = wall(rng);
      if (robot) {
        const float r = 0.9f + 0.2f * float(u) / w;
        s.rendered.at(u, v) = r;
        ++s.covered;
        const float c = u01(rng);
        z = c < 0.8f ? r + near(rng) : c < 0.9f ? r - 0.3f : wall(rng);
      }
      s.observed.at(u, v) = u01(rng) < 0.03f ? 0.f : z;
    }
  }
  return s;
}

// The depth model at the benchmark's resolution: its arguments are width
// and height (px).
DepthModelParams depth_model_at_resolution(const benchmark::State& state) {
  DepthModelParams p;
  p.width = int(state.range(0));
  p.height = int(state.range(1));
  return p;
}

// What the depth likelihood benchmarks share: a likelihood at the
// benchmark's resolution and a scene for it with 30% of the image covered.
struct DepthBench {
  explicit DepthBench(const benchmark::State& state)
      : params(depth_model_at_resolution(state)),
        likelihood(params),
        scene(make_scene(params.width, params.height, 0.3, 1)) {}

  // The covered pixels and the seconds per covered pixel (printed with an
  // SI prefix, e.g. 20n), so that resolutions and likelihood variants compare.
  void report_per_covered_pixel(benchmark::State& state) const {
    state.counters["covered_px"] = scene.covered;
    state.counters["time_per_covered_px"] =
        benchmark::Counter(double(scene.covered), benchmark::Counter::kIsIterationInvariantRate |
                                                      benchmark::Counter::kInvert);
  }

  const DepthModelParams params;
  DepthLikelihood likelihood;
  const Scene scene;
};

void BM_DepthLikelihood(benchmark::State& state) {
  DepthBench bench(state);
  bench.likelihood.set_observation(bench.scene.observed);
  for (auto _ : state) benchmark::DoNotOptimize(bench.likelihood.log_ratio(bench.scene.rendered));
  bench.report_per_covered_pixel(state);
}
BENCHMARK(BM_DepthLikelihood)->Args({80, 60})->Args({160, 120});

// The hot-loop variant: DepthLikelihood::ratios() (fast exp/erfc, four
// pixels at a time) on the same covered pixels, multiplied as the
// hypothesis evaluator does.
void BM_DepthLikelihoodFast(benchmark::State& state) {
  DepthBench bench(state);
  bench.likelihood.set_observation(bench.scene.observed);
  const DepthImage& rendered = bench.scene.rendered;
  std::vector<int> pixels;
  std::vector<float> depths;
  for (int i = 0; i < bench.params.width * bench.params.height; ++i) {
    if (rendered.depth_m[i] > 0) {
      pixels.push_back(i);
      depths.push_back(rendered.depth_m[i]);
    }
  }
  std::vector<float> ratios(pixels.size());
  for (auto _ : state) {
    bench.likelihood.ratios(pixels.data(), depths.data(), int(pixels.size()), ratios.data());
    double product = 1, log_sum = 0;
    for (size_t k = 0; k < ratios.size(); ++k) {
      product *= ratios[k];
      if (k % 8 == 7) {
        int e;
        product = std::frexp(product, &e);
        log_sum += e * 0.69314718055994531;
      }
    }
    benchmark::DoNotOptimize(log_sum + std::log(product));
  }
  bench.report_per_covered_pixel(state);
}
BENCHMARK(BM_DepthLikelihoodFast)->Args({80, 60})->Args({160, 120});

void BM_DepthSetObservation(benchmark::State& state) {
  DepthBench bench(state);
  for (auto _ : state) bench.likelihood.set_observation(bench.scene.observed);
}
BENCHMARK(BM_DepthSetObservation)->Args({80, 60})->Args({160, 120});

// The filter's own cost per image (sampling, weighting, resampling, moments,
// worker hand-off) with an evaluator that costs nothing: 28 coordinates,
// 5 blocks, L particles.
void BM_CpfOverhead(benchmark::State& state) {
  struct Cheap : PerParticleEvaluator {
    double log_likelihood(const ParticleBatch& b, int l, int) override {
      double s = 0;
      for (double x : b.particle(l)) s -= x * x;
      return s;
    }
  } cheap;
  const int n = 28;
  std::vector<SamplingBlock> blocks = {{"left_upper", {0, 1, 2, 3}},
                                       {"left_lower", {4, 5, 6}},
                                       {"right_upper", {7, 8, 9, 10}},
                                       {"right_lower", {11, 12, 13}},
                                       {"head_camera", {20, 21, 22, 23, 24, 25, 26, 27}}};
  CoordinateParticleFilterParams params;
  params.num_particles = int(state.range(0));
  CoordinateParticleFilter cpf(n, blocks, params);
  WorkerPool pool(int(state.range(1)));
  std::mt19937_64 rng(1);
  const std::vector<double> mean(n, 0.1), sd(n, 0.05);
  for (auto _ : state) {
    cpf.run(mean, sd, cheap, rng, pool);
    benchmark::DoNotOptimize(cpf.mean().data());
  }
  state.SetLabel(std::to_string(blocks.size()) + " blocks, " + std::to_string(pool.num_workers()) +
                 " workers");
}
BENCHMARK(BM_CpfOverhead)->Args({20, 1})->Args({200, 1})->Args({200, 2});

// uncertainty.model_error_learned_shifts, per image: one image's projected
// shift equations (every link shown, 3 columns each) added in the links'
// axes, then the solve. N links with geometry: arm7's 11, the dual arm's
// 23, and 60 for a larger maker description.
void BM_LearnedLinkShifts(benchmark::State& state) {
  const int links = int(state.range(0));
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  ImageInformation::ProjectedShiftEquations equations;
  for (int c = 0; c < 3 * links; ++c) equations.columns.push_back(c);
  Eigen::MatrixXd G(4 * links, 3 * links);
  for (int i = 0; i < G.size(); ++i) G.data()[i] = normal(rng);
  equations.A = G.transpose() * G;
  equations.b = Eigen::VectorXd::NullaryExpr(3 * links, [&] { return normal(rng); });
  equations.noise_var = 1.5;
  std::vector<Eigen::Isometry3d> T_link_camera(std::size_t(links), Eigen::Isometry3d::Identity());
  for (int k = 0; k < links; ++k)
    T_link_camera[std::size_t(k)].linear() =
        Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  LearnedLinkShifts learned(links, 10.0);
  double t_s = 0;
  for (auto _ : state) {
    learned.add_image(t_s, equations, T_link_camera, 0.3);
    learned.solve();
    benchmark::DoNotOptimize(learned.shift_m(0).data());
    t_s += 1.0 / 30;
  }
  state.SetLabel(std::to_string(links) + " links");
}
BENCHMARK(BM_LearnedLinkShifts)->Arg(11)->Arg(23)->Arg(60)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace arttrack

BENCHMARK_MAIN();
