// arttrack export SCENARIO.yaml [--seed S] [--set k=v ...] --out DIR
//
// Simulates run 0 of a scenario and writes it as a dataset (docs/datasets.md):
// the encoder readings and depth images exactly as the trackers of
// `arttrack run` receive them (corrupted, delayed, with stamps and arrival
// times), the ground truth at every scored instant, the camera, the nominal
// robot and the run's tracker configuration. `arttrack track DIR` then gives
// the numbers of `arttrack run` with the same seed.
#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include "arttrack/sim/dataset.h"
#include "arttrack/tracker/error.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

struct ExportArgs : ScenarioArgs {
  std::string out_dir;
  bool force = false;
};

void run_export(const ExportArgs& args) {
  check_fresh_output(args.out_dir, {"dataset.yaml", "joints.csv"}, args.force);
  const auto start = std::chrono::steady_clock::now();
  const sim::ExportSummary s =
      sim::export_scenario(args.scenario, args.overrides, args.seed, args.out_dir);
  std::cout << "wrote " << args.out_dir << ": " << s.joint_rows << " joint readings, "
            << s.frames_delivered << " depth images (" << s.frames_captured << " captured), "
            << s.truth_rows << " ground-truth rows; run seed " << s.run_seed << "; " << std::fixed
            << std::setprecision(1)
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
            << " s\n";
}

}  // namespace

void register_export(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "export", "Simulate a scenario and write what the tracker receives as a dataset",
      run_export);
  add_scenario_argument(cmd, args->scenario);
  add_seed_option(cmd, args->seed, "Scenario seed, as for arttrack run");
  add_set_option(cmd, args->overrides);
  add_out_and_force_options(cmd, args->out_dir, args->force, "Dataset folder to write",
                            "Overwrite a dataset already in --out")
      ->required();
}

}  // namespace arttrack::cli
