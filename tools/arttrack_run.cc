// arttrack run [SCENARIO.yaml] [--runs K] [--seed S] [--methods a,b] [--set k=v ...] [--out DIR]
//              [--force] [--realtime]
//
// Runs a scenario (default: scenarios/default.yaml): simulates the robot,
// tracks it with each method, scores them, prints a table of the
// end-effector errors (a row per end effector and the worst of them, with
// the lost runs), the consistency and camera errors and the timings, and
// writes DIR/summary.json, DIR/timeseries.csv, DIR/report.html and
// DIR/frames/ (default DIR: out/<scenario name>), all named on the closing
// line; a DIR holding a previous run's outputs is refused unless --force. summary.json records what
// reproduces the run (arttrack rerun DIR).
// Progress goes to stderr on long runs. --realtime simulates each run first,
// then replays its measurements at wall-clock speed to asynchronous trackers
// (image updates on their own threads, as on a robot, with the cores to
// themselves as a robot's camera leaves them) and prints, per method, the
// images dropped and the latency from capture to the estimate that includes
// the image.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
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

struct RunArgs : ScenarioArgs {
  int runs = 0;
  std::string methods;
  std::string out_dir;
  bool realtime = false;
  bool force = false;
};

// --realtime: per method, what the asynchronous tracker did with the images,
// how long each took from capture to the estimate, the searches among the
// image updates, and the slowest joint update (the joints never wait for an
// image update or a search: they run on the caller's thread meanwhile).
void print_realtime(std::ostream& os, const sim::ScenarioResult& result, double wall_s) {
  os << std::fixed << std::setprecision(1)
     << "real time: " << result.duration_s * double(result.runs.size())
     << " s of measurements replayed at the wall clock's pace to asynchronous trackers (" << wall_s
     << " s with simulating them first)\n"
     << "  method              received  applied  dropped (too old, backlog, busy)"
     << "  latency ms: p50     p99  update ms: p50    p99  searches  joint us: p99    max\n";
  for (std::size_t i = 0; i < result.method_results.size(); ++i) {
    const sim::MethodResult& m = result.method_results[i];
    int received = 0, applied = 0, old = 0, backlog = 0, busy = 0, searches = 0;
    for (const sim::RunResult& run : result.runs) {
      const TrackerStats& s = run.methods[i].stats;
      for (std::size_t k = 0; k < s.images.size(); ++k) searches += s.images[k].search_ms > 0;
      received += s.images_received;
      applied += s.images_applied;
      old += s.images_dropped_too_old;
      backlog += s.images_dropped_backlog;
      busy += s.images_dropped_busy;
    }
    std::ostringstream dropped;
    dropped << old + backlog + busy << " (" << old << ", " << backlog << ", " << busy << ")";
    os << "  " << std::left << std::setw(20) << m.method << std::right << std::setw(8) << received
       << std::setw(9) << applied << "  " << std::left << std::setw(32) << dropped.str()
       << std::right << std::setw(15) << m.timing.image_latency_ms.p50 << std::setw(8)
       << m.timing.image_latency_ms.p99 << std::setw(15) << m.timing.image_update_ms.p50
       << std::setw(7) << m.timing.image_update_ms.p99 << std::setw(10) << searches << std::setw(15)
       << m.timing.joint_update_us.p99 << std::setw(7) << m.timing.joint_update_us.max << "\n";
  }
  os.unsetf(std::ios::floatfield);
}

void run(const RunArgs& args) {
  const fs::path path =
      args.scenario.empty() ? sim::default_scenario_path() : fs::path(args.scenario);
  const sim::Scenario scenario = sim::load_scenario(path, args.overrides);
  if (args.runs < 0) throw UsageError("--runs must be >= 1");
  if (args.runs > kMaxRuns) throw UsageError("--runs must be at most " + std::to_string(kMaxRuns));

  sim::RunOptions options;
  options.runs = args.runs;
  options.seed = args.seed;
  options.methods = split_commas(args.methods);
  options.realtime = args.realtime;
  for (const std::string& m : options.methods) parse_method(m, "--methods");
  const fs::path out =
      args.out_dir.empty() ? fs::path("out") / scenario.name : fs::path(args.out_dir);
  run_and_write(scenario, options, out, args.force);
}

}  // namespace

void run_and_write(const sim::Scenario& scenario, sim::RunOptions options, const fs::path& out,
                   bool force) {
  // Before the run: a refusal should not cost its time.
  check_fresh_output(out, {"summary.json", "timeseries.csv"}, force);
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
  const std::vector<fs::path> written = sim::write_run_outputs(out, result);
  sim::print_summary_table(std::cout, result);
  if (options.realtime)
    print_realtime(std::cout, result, std::chrono::duration<double>(Clock::now() - start).count());
  std::cout << "wrote " << written_files_text(out, written) << " in " << std::fixed
            << std::setprecision(1) << std::chrono::duration<double>(Clock::now() - start).count()
            << " s\n";
}

std::string written_files_text(const fs::path& dir, const std::vector<fs::path>& files) {
  std::vector<std::string> items;
  std::vector<std::pair<fs::path, int>> folders;  // subfolder, files in it
  for (const fs::path& file : files) {
    const fs::path relative = file.lexically_relative(dir);
    if (!relative.has_parent_path()) {
      items.push_back(file.string());
      continue;
    }
    const fs::path folder = dir / *relative.begin();
    auto it = std::find_if(folders.begin(), folders.end(),
                           [&](const auto& f) { return f.first == folder; });
    if (it == folders.end()) it = folders.insert(folders.end(), {folder, 0});
    ++it->second;
  }
  for (const auto& [folder, count] : folders)
    items.push_back(folder.string() + "/ (" + std::to_string(count) +
                    (count == 1 ? " file)" : " files)"));
  std::string text;
  for (std::size_t i = 0; i < items.size(); ++i)
    text += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  return text;
}

void register_run(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "run",
      "Run a scenario: simulate, track with each method, score, write summary and series", run);
  add_scenario_argument(cmd, args->scenario, /*has_default=*/true);
  cmd->add_option("--runs", args->runs,
                  "Number of runs with different seeds (default: the scenario's)");
  add_seed_option(cmd, args->seed, "Scenario seed; run k uses a seed mixed from it and k");
  cmd->add_option("--methods", args->methods,
                  "Comma-separated methods: encoders_only, camera_offset_only, full_fusion, "
                  "vision_only (default: the scenario's)")
      ->check(comma_list());
  add_set_option(cmd, args->overrides);
  add_out_and_force_options(cmd, args->out_dir, args->force,
                            "Output folder (default: out/<scenario name>)");
  cmd->add_flag("--realtime", args->realtime,
                "Simulate each run, then replay it at wall-clock speed to asynchronous "
                "trackers; report dropped images and capture-to-estimate latency");
}

}  // namespace arttrack::cli
