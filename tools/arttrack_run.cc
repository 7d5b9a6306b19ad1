// arttrack run [SCENARIO.yaml] [--runs K] [--seed S] [--methods a,b] [--set k=v ...] [--out DIR]
//
// Runs a scenario (default: scenarios/default.yaml): simulates the robot,
// tracks it with each method, scores them, prints a table of the
// end-effector errors and timings, and writes DIR/summary.json,
// DIR/timeseries.csv and DIR/frames/ (default DIR: out/<scenario name>).
// Progress goes to stderr on long runs.
#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "arttrack/sim/run_outputs.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/tracker/error.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RunArgs {
  std::string scenario;
  int runs = 0;
  long long seed = -1;
  std::string methods;
  std::vector<std::string> overrides;
  std::string out_dir;
};

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

void run(const RunArgs& args) {
  const fs::path path =
      args.scenario.empty() ? sim::default_scenario_path() : fs::path(args.scenario);
  const sim::Scenario scenario = sim::load_scenario(path, args.overrides);
  if (args.runs < 0) throw InputError("--runs must be >= 1");
  if (args.seed < -1) throw InputError("--seed must be >= 0");

  sim::RunOptions options;
  options.runs = args.runs;
  options.seed = args.seed;
  options.methods = split_commas(args.methods);
  for (const std::string& m : options.methods) parse_method(m, "--methods");

  // Progress every few seconds of wall time, so short runs stay quiet.
  const auto start = Clock::now();
  auto last = start;
  options.progress = [&](const sim::RunProgress& p) {
    const auto now = Clock::now();
    if (now - last < std::chrono::seconds(3)) return;
    last = now;
    std::cerr << "arttrack run: run " << p.run + 1 << "/" << p.runs << ", " << std::fixed
              << std::setprecision(1) << p.time_s << "/" << p.duration_s << " s simulated, "
              << std::chrono::duration<double>(now - start).count() << " s elapsed\n";
    std::cerr.unsetf(std::ios::floatfield);
  };

  const sim::ScenarioResult result = sim::run_scenario(scenario, options);
  const fs::path out =
      args.out_dir.empty() ? fs::path("out") / scenario.name : fs::path(args.out_dir);
  sim::write_run_outputs(out, result);
  sim::print_summary_table(std::cout, result);
  std::cout << "wrote " << (out / "summary.json").string() << ", "
            << (out / "timeseries.csv").string() << " and " << (out / "frames").string() << "/ in "
            << std::fixed << std::setprecision(1)
            << std::chrono::duration<double>(Clock::now() - start).count() << " s\n";
}

}  // namespace

void register_run(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand(
      "run", "Run a scenario: simulate, track with each method, score, write summary and series");
  cmd->add_option("scenario", args->scenario, "Scenario YAML (default: scenarios/default.yaml)");
  cmd->add_option("--runs", args->runs,
                  "Number of runs with different seeds (default: the scenario's)");
  cmd->add_option("--seed", args->seed,
                  "Scenario seed; run k uses a seed mixed from it and k (default: the scenario's)");
  cmd->add_option("--methods", args->methods,
                  "Comma-separated methods: encoders_only, camera_offset_only, full_fusion, "
                  "vision_only (default: the scenario's)");
  cmd->add_option("--set", args->overrides, "Override a scenario key, e.g. --set duration_s=5")
      ->allow_extra_args(false);
  cmd->add_option("--out", args->out_dir, "Output folder (default: out/<scenario name>)");
  cmd->callback([args] { run(*args); });
}

}  // namespace arttrack::cli
