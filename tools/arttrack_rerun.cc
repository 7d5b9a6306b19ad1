// arttrack rerun RUN_DIR [--out DIR] [--force]
//
// Runs again the run whose outputs are in RUN_DIR (from `arttrack run` or a
// rerun) from what its summary.json records under "reproduce": the scenario
// after `extends` and every --set override, the tracker configuration, the
// seed, the number of runs and the methods (run_outputs.h). Writes the same
// outputs into DIR (default RUN_DIR/rerun): its timeseries.csv is
// byte-identical to RUN_DIR's, unless the scene, URDF or meshes the scenario
// names have changed since, or the run was --realtime (its timing is the
// machine's).
#include <CLI/CLI.hpp>

#include <filesystem>
#include <string>

#include "arttrack/sim/run_outputs.h"
#include "arttrack/sim/scenario.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;

struct RerunArgs {
  std::string run_dir;
  std::string out_dir;
  bool force = false;
};

void rerun(const RerunArgs& args) {
  const fs::path summary = fs::path(args.run_dir) / "summary.json";
  if (!fs::is_regular_file(summary))
    throw UsageError(args.run_dir + " is not a run's output folder: it has no summary.json");
  const sim::RunRecipe recipe = sim::read_run_recipe(summary);
  const sim::Scenario scenario = sim::scenario_from_recipe(recipe, summary.string());
  sim::RunOptions options;
  options.runs = recipe.runs;
  options.seed = (long long)recipe.seed;
  options.methods = recipe.methods;
  options.realtime = recipe.realtime;
  const fs::path out =
      args.out_dir.empty() ? fs::path(args.run_dir) / "rerun" : fs::path(args.out_dir);
  run_and_write(scenario, options, out, args.force);
}

}  // namespace

void register_rerun(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "rerun",
      "Run again a finished run from its output folder (its summary.json): same scenario, "
      "overrides, tracker configuration, seeds and methods; byte-identical timeseries.csv",
      rerun);
  cmd->add_option("run_dir", args->run_dir, "Output folder of the run (holds summary.json)")
      ->required()
      ->check(non_empty_name());
  add_out_and_force_options(cmd, args->out_dir, args->force,
                            "Output folder (default: RUN_DIR/rerun)");
}

}  // namespace arttrack::cli
