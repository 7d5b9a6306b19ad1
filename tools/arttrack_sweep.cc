// arttrack sweep SCENARIO.yaml --grid key=start:stop:step ... [--runs K]
//     [--seed S] [--methods a,b] [--set k=v ...] [--shard I/N] [--fail-threshold-m M]
//     [--fail-statistic STAT] [--out DIR]
//
// Runs the scenario in every cell of the Cartesian grid of the --grid keys,
// every method, K seeds per cell, and writes DIR/sweep.csv, DIR/sweep.html
// and DIR/sweep.json (default DIR: out/sweep_<scenario name>). With
// --shard I/N only cells with index % N == I run; `arttrack merge` combines
// the parts. Progress and the time left go to stderr; a table of the
// failure statistic per cell and method to stdout.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "arttrack/sim/sweep.h"
#include "arttrack/tracker/error.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct SweepArgs : ScenarioArgs {
  std::vector<std::string> grid;
  int runs = 0;
  std::string methods;
  std::string shard = "0/1";
  double fail_threshold_m = 0.05;
  std::string fail_statistic = "converged_p50_translation_m";
  std::string out_dir;
};

std::string duration_text(double s) {
  char buf[64];
  if (!std::isfinite(s)) return "?";
  if (s < 90)
    std::snprintf(buf, sizeof(buf), "%.0f s", s);
  else if (s < 5400)
    std::snprintf(buf, sizeof(buf), "%.0f min %02.0f s", std::floor(s / 60), std::fmod(s, 60));
  else
    std::snprintf(buf, sizeof(buf), "%.0f h %02.0f min", std::floor(s / 3600),
                  std::floor(std::fmod(s, 3600) / 60));
  return buf;
}

std::string joined(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

void sweep(const SweepArgs& args) {
  sim::SweepSpec spec;
  spec.scenario = fs::weakly_canonical(fs::absolute(args.scenario));
  spec.overrides = args.overrides;
  for (const std::string& g : args.grid) spec.axes.push_back(sim::parse_grid_axis(g));
  spec.methods = split_commas(args.methods);
  if (args.runs < 0) throw UsageError("--runs must be >= 1");
  if (args.runs > kMaxRuns) throw UsageError("--runs must be at most " + std::to_string(kMaxRuns));
  spec.runs = args.runs;
  spec.seed = args.seed;
  spec.fail_threshold_m = args.fail_threshold_m;
  spec.fail_statistic = args.fail_statistic;
  const sim::Shard shard = sim::parse_shard(args.shard);
  sim::resolve_sweep(spec);

  std::vector<std::size_t> cells;
  for (std::size_t c = 0; c < spec.cell_count(); ++c)
    if (shard.contains(c)) cells.push_back(c);
  const fs::path out = args.out_dir.empty() ? fs::path("out") / ("sweep_" + spec.scenario_name)
                                            : fs::path(args.out_dir);
  std::cerr << "arttrack sweep: " << spec.scenario_name << ", " << spec.cell_count() << " cells ("
            << cells.size() << " in shard " << shard.index << "/" << shard.count << "), "
            << spec.methods.size() << " methods, " << spec.runs
            << " run(s) per cell, scenario seed " << spec.scenario_seed << " -> " << out.string()
            << "\n";

  const auto start = Clock::now();
  auto last_report = start;
  std::vector<sim::CellResult> results;
  std::size_t failed = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::size_t cell = cells[i];
    const std::string label = joined(spec.cell_overrides(cell), " ");
    auto eta = [&](double fraction_of_cell) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      const double done = (double(i) + fraction_of_cell) / double(cells.size());
      return done > 0 ? elapsed * (1 - done) / done : INFINITY;
    };
    const auto progress = [&](const sim::RunProgress& p) {
      const auto now = Clock::now();
      if (now - last_report < std::chrono::seconds(5)) return;
      last_report = now;
      const double frac =
          (p.run + (p.duration_s > 0 ? p.time_s / p.duration_s : 0)) / std::max(1, p.runs);
      std::cerr << "arttrack sweep: cell " << i + 1 << "/" << cells.size() << " [" << label
                << "] run " << p.run + 1 << "/" << p.runs << ", " << std::fixed
                << std::setprecision(1) << p.time_s << "/" << p.duration_s << " s simulated; "
                << duration_text(eta(frac)) << " left\n";
      std::cerr.unsetf(std::ios::floatfield);
    };
    const auto cell_start = Clock::now();
    results.push_back(sim::run_sweep_cell(spec, cell, progress));
    const sim::CellResult& r = results.back();
    failed += r.failed;
    std::cerr << "arttrack sweep: cell " << i + 1 << "/" << cells.size() << " [" << label << "] "
              << (r.failed ? "FAILED: " + r.message : std::string("done")) << " ("
              << duration_text(std::chrono::duration<double>(Clock::now() - cell_start).count())
              << "); " << duration_text(eta(1.0)) << " left\n";
    last_report = Clock::now();
    // Outputs after every cell, so a stopped job leaves what it did.
    sim::write_sweep_outputs(out, spec, shard, results);
  }
  if (cells.empty()) sim::write_sweep_outputs(out, spec, shard, results);

  // The failure statistic per cell and method, in mm (translations).
  const auto& stats = sim::sweep_statistics();
  const std::size_t s =
      std::size_t(std::find(stats.begin(), stats.end(), spec.fail_statistic) - stats.begin());
  const sim::StatisticUnit unit = sim::statistic_unit(spec.fail_statistic);
  std::cout << spec.fail_statistic << " in " << unit.shown << " (* = above "
            << spec.fail_threshold_m * unit.scale << " " << unit.shown << ": --fail-threshold-m "
            << spec.fail_threshold_m << ", in " << unit.si << ")\n";
  std::cout << std::left << std::setw(6) << "cell";
  std::size_t width = 10;
  for (const sim::GridAxis& a : spec.axes) width = std::max(width, a.key.size() + 2);
  for (const sim::GridAxis& a : spec.axes) std::cout << std::setw(int(width)) << a.key;
  for (const std::string& m : spec.methods)
    std::cout << std::setw(int(std::max<std::size_t>(m.size() + 2, 12))) << m;
  std::cout << "\n";
  for (const sim::CellResult& r : results) {
    std::cout << std::setw(6) << r.cell;
    const auto coord = spec.cell_coordinates(r.cell);
    for (std::size_t a = 0; a < spec.axes.size(); ++a)
      std::cout << std::setw(int(width)) << spec.axes[a].values[coord[a]];
    if (r.failed) {
      std::cout << "failed: " << r.message << "\n";
      continue;
    }
    for (std::size_t m = 0; m < spec.methods.size(); ++m) {
      const double v = r.stats[m][s];
      std::ostringstream cellv;
      if (std::isfinite(v))
        cellv << std::fixed << std::setprecision(2) << v * unit.scale
              << (v > spec.fail_threshold_m ? "*" : "");
      else
        cellv << v;
      std::cout << std::setw(int(std::max<std::size_t>(spec.methods[m].size() + 2, 12)))
                << cellv.str();
    }
    std::cout << "\n";
  }
  std::cout << std::right << results.size() << " cells, " << failed << " failed to run; wrote "
            << (out / "sweep.csv").string() << ", " << (out / "sweep.html").string() << " in "
            << duration_text(std::chrono::duration<double>(Clock::now() - start).count()) << "\n";
}

}  // namespace

void register_sweep(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "sweep",
      "Run a scenario over a grid of scenario keys (stress sweep): sweep.csv, sweep.html", sweep);
  add_scenario_argument(cmd, args->scenario);
  cmd->add_option("--grid", args->grid,
                  "Swept key: key=start:stop:step (stop included) or key=v1,v2,...; keys as "
                  "--set takes them, list elements as encoders[0].offset_deg")
      ->required()
      ->allow_extra_args(false);
  cmd->add_option("--runs", args->runs, "Runs (seeds) per cell (default: the scenario's)");
  add_seed_option(cmd, args->seed,
                  "Scenario seed; each cell's seed is mixed from it and the cell's overrides");
  cmd->add_option("--methods", args->methods, "Comma-separated methods (default: the scenario's)")
      ->check(comma_list());
  add_set_option(cmd, args->overrides, "Fixed override of a scenario key, e.g. duration_s=5");
  cmd->add_option("--shard", args->shard,
                  "Run only cells with index % N == I, as I/N (merge the parts with arttrack "
                  "merge)");
  cmd->add_option("--fail-threshold-m", args->fail_threshold_m,
                  "A method fails in a cell where the failure statistic exceeds this, in metres "
                  "(default 0.05 m = 50 mm; the table and sweep.html show mm; rad or s for a "
                  "rotation or time --fail-statistic)");
  cmd->add_option("--fail-statistic", args->fail_statistic,
                  "Statistic compared with --fail-threshold-m (default "
                  "converged_p50_translation_m)");
  add_out_option(cmd, args->out_dir, "Output folder (default: out/sweep_<scenario name>)");
}

}  // namespace arttrack::cli
