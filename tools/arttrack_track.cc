// arttrack track DATASET [--config TRACKER.yaml] [--urdf ROBOT.urdf] [--methods a,b]
//                        [--every N] --out DIR
//
// Tracks a dataset (docs/datasets.md; simulated by `arttrack export` or
// recorded on a robot) with each method, synchronously, feeding joint
// readings and depth images in arrival order. Writes DIR/estimate.csv (the
// estimate over time) and, when the dataset has ground truth, the outputs of
// `arttrack run` (summary.json, timeseries.csv, frames/) and its table.
// Missing or unreadable frames are skipped with a warning on stderr.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "arttrack/sim/dataset_tracking.h"
#include "arttrack/sim/run_outputs.h"
#include "arttrack/tracker/error.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;

struct TrackArgs {
  std::string dataset, config, urdf, methods, out_dir;
  int every = 0;
  bool force = false;
};

void run_track(const TrackArgs& args) {
  if (args.every < 0) throw UsageError("--every must be >= 0");
  std::optional<fs::path> urdf;
  if (!args.urdf.empty()) urdf = args.urdf;
  const sim::Dataset dataset = sim::load_dataset(args.dataset, urdf);

  sim::TrackOptions options;
  options.methods = split_commas(args.methods);
  if (!args.config.empty()) options.tracker_config = args.config;
  options.estimate_every_n_joints = args.every;
  options.warn = [](const std::string& w) {
    std::cerr << "arttrack track: warning: " << w << "\n";
  };

  const fs::path out = args.out_dir;
  check_fresh_output(out, {"estimate.csv", "summary.json"}, args.force);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(out.string() + ": cannot create: " + ec.message());
  std::ofstream estimate(out / "estimate.csv");
  if (!estimate) throw InputError((out / "estimate.csv").string() + ": cannot open for writing");
  const sim::TrackResult r = sim::track_dataset(dataset, options, &estimate);
  estimate.close();
  if (!estimate) throw InputError((out / "estimate.csv").string() + ": write failed");

  for (const sim::MethodRun& m :
       r.result.runs.empty() ? std::vector<sim::MethodRun>{} : r.result.runs[0].methods)
    if (m.stats.joint_measurements_dropped || m.stats.images_dropped_bad_stamp)
      std::cerr << "arttrack track: " << m.method << " dropped "
                << m.stats.joint_measurements_dropped
                << " joint measurements (a reading outside its joint's limits or not finite) and "
                << m.stats.images_dropped_bad_stamp << " images (stamp off the joint clock)\n";
  if (r.frames_missing > 0)
    std::cerr << "arttrack track: " << r.frames_missing << " of " << dataset.frames.size()
              << " depth images missing or unreadable, skipped\n";
  if (dataset.has_truth()) {
    std::vector<fs::path> written{out / "estimate.csv"};
    for (const fs::path& file : sim::write_run_outputs(out, r.result)) written.push_back(file);
    sim::print_summary_table(std::cout, r.result);
    std::cout << "wrote " << written_files_text(out, written) << "\n";
  } else {
    std::cout << "no ground truth: wrote " << (out / "estimate.csv").string() << " only\n";
  }
}

}  // namespace

void register_track(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "track", "Track a recorded or exported dataset; score it if it has ground truth",
      run_track);
  cmd->add_option("dataset", args->dataset, "Dataset folder (docs/datasets.md)")->required();
  cmd->add_option("--config", args->config,
                  "Tracker configuration (default: the dataset's tracker.yaml, else "
                  "the built-in tracker/config/default.yaml)");
  cmd->add_option("--urdf", args->urdf, "Nominal robot URDF (default: the dataset's)");
  cmd->add_option("--methods", args->methods,
                  "Comma-separated methods: encoders_only, camera_offset_only, full_fusion, "
                  "vision_only (default: the dataset's, else all it allows)")
      ->check(comma_list());
  cmd->add_option("--every", args->every,
                  "Also write an estimate.csv row every N joint readings (default 0)");
  add_out_and_force_options(cmd, args->out_dir, args->force, "Output folder")->required();
}

}  // namespace arttrack::cli
