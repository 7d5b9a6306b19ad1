// arttrack tune SCENARIOS... --params key=lo:hi,... [--objective STAT]
//     [--budget N] [--validate SCENARIOS...] [--optimizer bobyqa|cobyla|neldermead|direct]
//     [--config BASE.yaml] [--tracker-method M] [--time-penalty W] [--runs K]
//     [--seed S] [--set k=v ...] [--out DIR]
//
// Tunes tracker parameters (keys of the tracker YAML) by derivative-free
// minimisation of a statistic over several scenarios at once (sim/tuning.h),
// then compares the tuned configuration with the base one on the tuning and
// validation scenarios. Writes DIR/tuned.yaml, DIR/search.csv,
// DIR/tuning.html and DIR/candidates/ (default DIR: out/tune). Each
// evaluation is reported on stderr. --optimizer picks NLopt's algorithm
// (--methods and --tracker-method pick tracking methods, everywhere).
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include "arttrack/sim/tuning.h"
#include "arttrack/tracker/error.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;

struct TuneArgs {
  std::vector<std::string> scenarios;
  std::vector<std::string> params;
  std::string objective = "mean_converged_p75_translation_m";
  int budget = 30;
  std::vector<std::string> validation;
  std::string optimizer = "bobyqa";
  std::string old_method;  // --method, the old name of --optimizer
  std::string config;
  std::string tracker_method = "full_fusion";
  double time_penalty = 0;
  int runs = 0;
  long long seed = -1;
  std::vector<std::string> overrides;
  std::string out_dir = "out/tune";
};

void tune(const TuneArgs& args) {
  sim::TuningOptions o;
  for (const std::string& s : args.scenarios) o.scenarios.push_back(s);
  for (const std::string& s : args.validation) o.validation.push_back(s);
  o.scenario_overrides = args.overrides;
  o.base_config = args.config.empty()
                      ? fs::path(ARTTRACK_SOURCE_DIR) / "tracker/config/default.yaml"
                      : fs::path(args.config);
  o.parameter_specs = args.params;
  o.objective = sim::parse_objective(args.objective);
  o.objective.method = args.tracker_method;
  o.objective.time_penalty_per_ms = args.time_penalty;
  if (!args.old_method.empty())
    throw UsageError(
        "tune --method is now --optimizer (--methods and --tracker-method pick "
        "tracking methods)");
  try {
    o.optimizer = sim::parse_optimizer(args.optimizer);
  } catch (const InputError& e) {
    throw UsageError(e.what());
  }
  o.budget = args.budget;
  o.runs = args.runs;
  o.seed = args.seed;
  o.out_dir = args.out_dir;
  o.log = [](const std::string& line) { std::cerr << "arttrack tune: " << line << "\n"; };

  const sim::TuningResult r = sim::tune(o);
  const sim::Evaluation& best = r.history[r.best];
  std::cout << "best of " << r.history.size() << " evaluations by "
            << sim::optimizer_name(o.optimizer) << " (" << r.optimizer.stop << "): evaluation "
            << best.index << ", " << o.objective.text() << " = " << best.objective << "\n";
  for (std::size_t i = 0; i < r.params.size(); ++i)
    std::cout << "  " << r.params[i].key << ": " << r.params[i].text(best.values[i]) << " (default "
              << (std::isnan(r.default_values[i]) ? std::string("-")
                                                  : r.params[i].text(r.default_values[i]))
              << ", interval [" << r.params[i].text(r.params[i].lo) << ", "
              << r.params[i].text(r.params[i].hi) << "])\n";
  std::cout << o.objective.statistic << " of " << o.objective.method << ", default -> tuned:\n";
  for (std::size_t i = 0; i < r.compare_default.size(); ++i)
    std::cout << "  " << std::left << std::setw(24) << r.compare_default[i].name << std::right
              << std::setw(11) << (r.compare_is_validation[i] ? "validation" : "tuning") << "  "
              << r.compare_default[i].objective_statistic << " -> "
              << r.compare_tuned[i].objective_statistic << "\n";
  const fs::path out(o.out_dir);
  std::cout << "wrote " << (out / "tuned.yaml").string() << ", " << (out / "search.csv").string()
            << ", " << (out / "tuning.html").string() << "\n";
}

}  // namespace

void register_tune(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "tune",
      "Tune tracker parameters over scenarios (NLopt): tuned.yaml, search.csv, tuning.html", tune);
  cmd->add_option("scenarios", args->scenarios, "Scenarios tuned on")->required();
  cmd->add_option("--params", args->params,
                  "Tuned tracker keys: key=lo:hi[,key=lo:hi...] (:int for whole numbers)")
      ->required()
      ->allow_extra_args(false);
  cmd->add_option(
      "--objective", args->objective,
      "mean_STAT or max_STAT over scenarios (default mean_converged_p75_translation_m)");
  cmd->add_option("--budget", args->budget, "Objective evaluations at most (default 30)");
  cmd->add_option("--validate", args->validation, "Scenarios only compared at the end");
  cmd->add_option("--optimizer", args->optimizer,
                  "NLopt algorithm: bobyqa (default), cobyla, neldermead or direct");
  cmd->add_option("--method", args->old_method)->group("");  // hidden: names --optimizer
  cmd->add_option("--config", args->config,
                  "Base tracker configuration (default tracker/config/default.yaml)");
  cmd->add_option("--tracker-method", args->tracker_method,
                  "Tracking method scored (default full_fusion)");
  cmd->add_option("--time-penalty", args->time_penalty,
                  "Add W x the mean p50 image update time (ms) to the objective");
  cmd->add_option("--runs", args->runs, "Runs per scenario (default: each scenario's)");
  add_seed_option(cmd, args->seed,
                  "Seed of each scenario, the same for every candidate and the final comparison");
  add_set_option(cmd, args->overrides, "Override a key of every scenario, e.g. duration_s=5");
  add_out_option(cmd, args->out_dir, "Output folder (default out/tune)");
}

}  // namespace arttrack::cli
