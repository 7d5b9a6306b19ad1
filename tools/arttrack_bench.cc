// arttrack bench [SCENARIO.yaml] [--evaluations N] [--resolution WxH] [--json FILE]
//                [--seed S] [--set k=v ...] [--threads T]
//                [--soak MINUTES [--soak-frames K]]
//
// How fast the full-fusion tracker runs on a scenario's measurement stream
// (default: scenarios/default.yaml). The scenario runner simulates run 0 and
// hands every encoder reading and depth image, as a tracker receives them,
// to one synchronous full-fusion tracker, which processes each at once: only
// the tracker's calls are timed, the simulation is not. Prints and writes
// (--json) the joint update time, the image update and re-filtering times
// (the tracker's own timings): over all images, over the steady state (the
// images at which no acquisition or re-acquisition search ran) and the
// searches' own count and durations; the sampling blocks, the triangles of
// the model and those the tracker draws (TrackerConfig::geometry) and the
// time to prepare them (Tracker::prepare_camera, before the stream, untimed
// otherwise),
// likelihood evaluations per image, and the
// realtime factor: stream duration / total (wall) time in the tracker's
// calls. Also the CPU time of those calls, all threads: on a machine shared
// with other jobs, the work the tracker did (wall time grows with the load).
// Also scores the tracker's end-effector error against the ground truth at
// the scenario's scored instants (all samples and converged ones).
//
// --evaluations N sets particles = ceil(N / blocks sampled per image) and
// min_evaluations 0 (sampling_blocks(): by default one per joint whose bias
// is estimated and one per camera-offset joint, of which
// particle_filter.camera_blocks_per_image are sampled per image); without
// it the configuration's particles, at least
// particle_filter.min_evaluations per image. --resolution sets the
// likelihood resolution (images are subsampled to it).
//
// --soak MINUTES: instead, feeds one tracker MINUTES of stream as fast as it
// can and prints its resident memory (arttrack_bench_soak.h); fails when it
// grows by more than 1 MB after the first minute.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/scoring.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/worker_pool.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack_bench_soak.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

struct BenchArgs : ScenarioArgs {
  int evaluations = 0;
  std::string resolution;
  std::string json_path;
  int threads = -1;
  double soak_minutes = 0;
  int soak_frames = 30;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU time of the whole process (all threads), s.
double process_cpu_s() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Feeds the stream to one full-fusion tracker, timing its calls, and scores
// its estimate at every scored instant.
class BenchSink : public sim::MeasurementSink {
 public:
  BenchSink(std::shared_ptr<const RobotModel> robot, TrackerConfig config)
      : robot_(std::move(robot)), config_(std::move(config)) {}

  void begin_run(const sim::RunStart& start) override {
    config_.seed = start.tracker_seed;
    tracker_ = std::make_unique<Tracker>(robot_, config_, start.encoder_joints);
    camera_ = start.camera;
    // Before the stream, as a live run does (Tracker::prepare_camera): timed
    // apart, not part of the image updates or the realtime factor.
    const auto prepare_start = Clock::now();
    tracker_->prepare_camera(camera_);
    prepare_ms_ = 1e3 * seconds_since(prepare_start);
    trace_ = sim::ErrorTrace(0, start.end_effectors.size());
  }

  void joints(int, double time_s, std::span<const double> readings_rad) override {
    const double cpu = process_cpu_s();
    const auto start = Clock::now();
    tracker_->add_joint_measurement(time_s, readings_rad);
    const double s = seconds_since(start);
    joint_update_us_.push_back(1e6 * s);
    processing_s_ += s;
    cpu_s_ += process_cpu_s() - cpu;
  }

  void image(int, double stamp_s, double, const DepthImage& image) override {
    const double cpu = process_cpu_s();
    const auto start = Clock::now();
    tracker_->add_depth_image(stamp_s, image, camera_);
    processing_s_ += seconds_since(start);
    cpu_s_ += process_cpu_s() - cpu;
  }

  void truth(int, const sim::TruthSample& truth) override {
    // One sample per instant with every end effector (scored as `run`
    // does: per end effector and the worst of them).
    const TrackerEstimate e = tracker_->estimate();
    sim::ScoredSample sample;
    sample.time_s = truth.time_s;
    for (std::size_t k = 0; k < truth.T_camera_ee.size(); ++k)
      sample.end_effectors.push_back(sim::pose_error(e.T_camera_ee[k], truth.T_camera_ee[k]));
    trace_.add(sample);
  }

  const Tracker& tracker() const { return *tracker_; }
  const std::vector<double>& joint_update_us() const { return joint_update_us_; }
  double processing_s() const { return processing_s_; }
  double cpu_s() const { return cpu_s_; }
  double prepare_ms() const { return prepare_ms_; }
  const sim::ErrorTrace& trace() const { return trace_; }

 private:
  std::shared_ptr<const RobotModel> robot_;
  TrackerConfig config_;
  std::unique_ptr<Tracker> tracker_;
  CameraIntrinsics camera_;
  std::vector<double> joint_update_us_;
  double processing_s_ = 0, cpu_s_ = 0, prepare_ms_ = 0;
  sim::ErrorTrace trace_;
};

Json p50_p99(const sim::Percentiles& p) { return Json{{"p50", p.p50}, {"p99", p.p99}}; }

Json all_percentiles(const sim::Percentiles& p) {
  return Json{{"count", p.count}, {"p01", p.p01}, {"p25", p.p25},  {"p50", p.p50},
              {"p75", p.p75},     {"p99", p.p99}, {"mean", p.mean}};
}

void run_bench(const BenchArgs& args) {
  const fs::path path =
      args.scenario.empty() ? sim::default_scenario_path() : fs::path(args.scenario);
  sim::Scenario scenario = sim::load_scenario(path, args.overrides);
  if (args.evaluations < 0) throw UsageError("--evaluations must be >= 1");
  if (args.evaluations > kMaxEvaluations)
    throw UsageError("--evaluations must be at most " + std::to_string(kMaxEvaluations));

  TrackerConfig config = scenario.tracker;
  config.source = scenario.tracker_document.file;
  config.method = TrackingMethod::kFullFusion;
  config.asynchronous = false;
  if (args.threads >= 0) config.threads = args.threads;
  if (!args.resolution.empty()) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    std::istringstream in(args.resolution);
    if (!(in >> w >> x >> h) || x != 'x' || in >> extra || w <= 0 || h <= 0)
      throw UsageError("--resolution '" + args.resolution + "': expected WIDTHxHEIGHT, e.g. 80x60");
    if (w > kMaxResolution || h > kMaxResolution)
      throw UsageError("--resolution '" + args.resolution + "': width and height must be at most " +
                       std::to_string(kMaxResolution));
    config.depth_model.width = w;
    config.depth_model.height = h;
  }

  // The tracker's nominal robot, as the runner builds it.
  auto robot = std::make_shared<const RobotModel>(
      sim::tracker_robot_model(scenario.scene, scenario.tracker_urdf()));
  config.validate(config.source);
  const std::vector<SamplingBlock> sampling = sampling_blocks(*robot, config);
  const int blocks = int(sampling.size());
  // Full fusion samples particle_filter.camera_blocks_per_image of the
  // camera blocks per image.
  const int sampled_blocks = blocks_sampled_per_image(sampling, *robot, config);
  if (args.evaluations > 0) {
    config.particle_filter.num_particles = (args.evaluations + sampled_blocks - 1) / sampled_blocks;
    config.min_evaluations = 0;
  }
  config.validate(config.source);
  const int particles = particle_filter_params(config, sampled_blocks).num_particles;
  if (args.soak_minutes > 0) {
    SoakOptions soak;
    soak.minutes = args.soak_minutes;
    soak.frames = args.soak_frames;
    soak.seed = args.seed;
    run_soak(std::move(scenario), robot, config, soak);
    return;
  }

  BenchSink sink(robot, config);
  sim::RunOptions options;
  options.runs = 1;
  options.seed = args.seed;
  options.methods = {method_name(TrackingMethod::kEncodersOnly)};  // the runner's own: cheap
  options.frames_to_keep = 0;
  options.sink = &sink;
  const auto start = Clock::now();
  auto last = start;
  options.progress = [&](const sim::RunProgress& p) {
    if (Clock::now() - last < std::chrono::seconds(5)) return;
    last = Clock::now();
    std::cerr << "arttrack bench: " << std::fixed << std::setprecision(1) << p.time_s << "/"
              << p.duration_s << " s simulated, " << seconds_since(start) << " s elapsed\n";
    std::cerr.unsetf(std::ios::floatfield);
  };
  const sim::ScenarioResult result = sim::run_scenario(scenario, options);

  const TrackerStats stats = sink.tracker().stats();
  const sim::Percentiles joint_us = sim::percentiles(sink.joint_update_us());
  const sim::Percentiles image_ms = sim::percentiles(stats.images.values(&ImageTiming::update_ms));
  // The steady state: images at which no search ran; and the searches.
  std::vector<double> steady, searches;
  for (std::size_t k = 0; k < stats.images.size(); ++k) {
    const ImageTiming& t = stats.images[k];
    (t.search_ms > 0 ? searches : steady).push_back(t.update_ms);
  }
  const sim::Percentiles steady_ms = sim::percentiles(steady);
  const sim::Percentiles search_ms = sim::percentiles(searches);
  const double search_max_ms = search_ms.max;
  const sim::Percentiles refilter_ms =
      sim::percentiles(stats.images.values(&ImageTiming::refilter_ms));
  sim::MethodScores scores(method_name(TrackingMethod::kFullFusion), {},
                           scenario.scoring.end_effectors);
  scores.add_run(sink.trace());
  const sim::MethodSummary summary = scores.summary(scenario.scoring.options);
  const double realtime_factor = result.duration_s / sink.processing_s();
  const double evaluations_per_image =
      stats.images_applied ? double(stats.likelihood_evaluations) / stats.images_applied : 0.0;
  const std::string resolution =
      std::to_string(config.depth_model.width) + "x" + std::to_string(config.depth_model.height);
  const int threads =
      config.threads > 0 ? config.threads : int(std::max(1u, std::thread::hardware_concurrency()));

  Json j;
  j["scenario"] = scenario.name;
  j["source"] = scenario.source;
  j["duration_s"] = result.duration_s;
  j["run_seed"] = result.seeds.at(0);
  j["resolution"] = resolution;
  j["particles"] = particles;
  j["blocks"] = blocks;
  j["blocks_sampled_per_image"] = sampled_blocks;
  j["block_names"] = Json::array();
  for (const SamplingBlock& b : sampling) j["block_names"].push_back(b.name);
  j["triangles"] = {{"model", stats.model_triangles},
                    {"drawn", stats.drawn_triangles},
                    {"max_error_px", config.geometry.max_error_px},
                    {"error_bound_m", stats.mesh_error_bound_m},
                    {"simplifier_error_m", stats.mesh_error_m},
                    {"prepare_ms", sink.prepare_ms()}};
  const std::string mesh_parts = describe_mesh_parts(*robot);
  j["mesh_parts"] = mesh_parts;
  j["evaluations_per_image"] = evaluations_per_image;
  j["threads"] = threads;
  j["joint_measurements"] = stats.joint_measurements;
  j["joint_measurements_dropped"] = stats.joint_measurements_dropped;
  j["images"] = {{"received", stats.images_received},
                 {"dropped_bad_stamp", stats.images_dropped_bad_stamp},
                 {"applied", stats.images_applied},
                 {"dropped_too_old", stats.images_dropped_too_old},
                 {"dropped_backlog", stats.images_dropped_backlog},
                 {"dropped_busy", stats.images_dropped_busy}};
  j["joint_update_us"] = p50_p99(joint_us);
  j["refilter_ms"] = p50_p99(refilter_ms);
  j["image_update_ms"] = p50_p99(image_ms);
  j["steady_image_update_ms"] =
      Json{{"count", steady_ms.count}, {"p50", steady_ms.p50}, {"p99", steady_ms.p99}};
  j["searches"] = Json{{"count", search_ms.count},
                       {"p50_ms", search_ms.count ? Json(search_ms.p50) : Json(nullptr)},
                       {"max_ms", search_ms.count ? Json(search_max_ms) : Json(nullptr)}};
  j["processing_s"] = sink.processing_s();
  j["processing_cpu_s"] = sink.cpu_s();
  j["realtime_factor"] = realtime_factor;
  j["error"] = {
      {"converged_after_s", scenario.scoring.options.converged_after_s},
      {"translation_m", all_percentiles(summary.all.translation_m)},
      {"converged_translation_m", all_percentiles(summary.converged.translation_m)},
      {"converged_rotation_rad", all_percentiles(summary.converged.rotation_rad)},
      {"convergence_threshold_m", scenario.scoring.options.convergence_threshold_m},
      // First time after which the error stays below the threshold (null: never).
      {"time_to_converge_s",
       summary.time_to_converge_s.at(0) ? Json(*summary.time_to_converge_s.at(0)) : Json(nullptr)}};

  std::cout << std::fixed << std::setprecision(3);
  std::cout << "arttrack bench: " << scenario.name << ", " << result.duration_s
            << " s of stream, full fusion at " << resolution << ", " << particles << " particles x "
            << sampled_blocks << " of " << blocks << " blocks = " << evaluations_per_image
            << " evaluations per image, " << threads << " threads\n";
  std::cout << "  blocks           ";
  for (std::size_t b = 0; b < sampling.size(); ++b)
    std::cout << (b ? ", " : "") << sampling[b].name;
  std::cout << "\n";
  std::cout << "  triangles        " << stats.model_triangles << " in the model, "
            << stats.drawn_triangles << " drawn (" << config.geometry.max_error_px << " px at "
            << config.geometry.nearest_range_m << " m: at most " << 1e3 * stats.mesh_error_bound_m
            << " mm; the simplifier reports " << 1e3 * stats.mesh_error_m << " mm), prepared in "
            << sink.prepare_ms() << " ms before the stream\n";
  std::cout << "  meshes           " << mesh_parts << "\n";
  std::cout << "  joint update     p50 " << joint_us.p50 << " us, p99 " << joint_us.p99 << " us ("
            << stats.joint_measurements << ", " << stats.joint_measurements_dropped
            << " dropped)\n";
  std::cout << "  image update     p50 " << image_ms.p50 << " ms, p99 " << image_ms.p99 << " ms ("
            << stats.images_applied << " of " << stats.images_received << " applied, "
            << stats.images_dropped_bad_stamp << " dropped off the joint clock)\n";
  std::cout << "  steady state     p50 " << steady_ms.p50 << " ms, p99 " << steady_ms.p99 << " ms ("
            << steady_ms.count << " images without a search)\n";
  std::cout << "  searches         " << search_ms.count;
  if (search_ms.count)
    std::cout << ", p50 " << search_ms.p50 << " ms, max " << search_max_ms << " ms";
  std::cout << "\n";
  std::cout << "  of which refilter p50 " << refilter_ms.p50 << " ms, p99 " << refilter_ms.p99
            << " ms\n";
  std::cout << "  realtime factor  " << std::setprecision(2) << realtime_factor << " ("
            << std::setprecision(3) << sink.processing_s() << " s in the tracker for "
            << result.duration_s << " s of data; " << sink.cpu_s() << " s of CPU)\n";
  std::cout << "  ee translation error: all p50 " << 1e3 * summary.all.translation_m.p50
            << " mm; after " << scenario.scoring.options.converged_after_s << " s p25 "
            << 1e3 * summary.converged.translation_m.p25 << ", p50 "
            << 1e3 * summary.converged.translation_m.p50 << ", p75 "
            << 1e3 * summary.converged.translation_m.p75 << ", p99 "
            << 1e3 * summary.converged.translation_m.p99 << " mm; below "
            << 1e3 * scenario.scoring.options.convergence_threshold_m << " mm from "
            << (summary.time_to_converge_s.at(0)
                    ? std::to_string(*summary.time_to_converge_s.at(0)) + " s on"
                    : std::string("never"))
            << "\n";
  if (!args.json_path.empty()) {
    std::ofstream out(args.json_path);
    if (!out) throw InputError(args.json_path + ": cannot open for writing");
    out << j.dump(2) << "\n";
    if (!out) throw InputError(args.json_path + ": write failed");
    std::cout << "wrote " << args.json_path << "\n";
  }
}

}  // namespace

void register_bench(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "bench", "Time the full-fusion tracker on a scenario's measurement stream", run_bench);
  add_scenario_argument(cmd, args->scenario, /*has_default=*/true);
  cmd->add_option(
      "--evaluations", args->evaluations,
      "Likelihood evaluations per image: particles = ceil(N / blocks sampled per image) "
      "(default: the tracker configuration's particles)");
  cmd->add_option("--resolution", args->resolution,
                  "Likelihood resolution WIDTHxHEIGHT (default: the tracker configuration's)");
  cmd->add_option("--json", args->json_path, "Also write the figures to this JSON file");
  add_seed_option(cmd, args->seed, "Scenario seed; the benchmark simulates its run 0");
  add_set_option(cmd, args->overrides);
  cmd->add_option("--threads", args->threads,
                  "Image update worker threads, 0 = one per core, at most " +
                      std::to_string(kMaxWorkerThreads) + " (default: the configuration's)")
      ->check(CLI::Range(0, kMaxWorkerThreads));
  cmd->add_option("--soak", args->soak_minutes,
                  "Instead: feed one tracker this many minutes of stream (1 kHz joints, 30 Hz "
                  "images) and check that its resident memory stays within 1 MB after minute 1")
      ->check(CLI::Range(1.0, 1440.0));
  cmd->add_option("--soak-frames", args->soak_frames,
                  "Distinct depth images the soak reuses (default 30)")
      ->check(CLI::Range(1, 3000));
}

}  // namespace arttrack::cli
