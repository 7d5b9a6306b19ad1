// Running one cell of a sweep: the scenario with the cell's overrides and
// seed, every method, its statistics; a failure is recorded, not thrown.
#include <algorithm>

#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/sweep.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"

namespace arttrack::sim {

CellResult run_sweep_cell(const SweepSpec& spec, std::size_t cell,
                          const std::function<void(const RunProgress&)>& progress) {
  CellResult r;
  r.cell = cell;
  const std::vector<std::string> cell_over = spec.cell_overrides(cell);
  r.seed = cell_seed(cell_over, spec.scenario_seed);
  const auto& stats = sweep_statistics();
  r.stats.assign(spec.methods.size(), std::vector<double>(stats.size(), kNaN));
  try {
    std::vector<std::string> overrides = spec.overrides;
    overrides.insert(overrides.end(), cell_over.begin(), cell_over.end());
    const Scenario scenario = load_scenario(spec.scenario, overrides);
    RunOptions options;
    options.runs = spec.runs;
    options.seed = (long long)r.seed;
    options.methods = spec.methods;
    options.progress = progress;
    options.frames_to_keep = 0;
    const ScenarioResult result = run_scenario(scenario, options);
    for (std::size_t m = 0; m < spec.methods.size(); ++m) {
      const MethodResult* mr = result.method(spec.methods[m]);
      if (!mr) throw InputError("the runner returned no result for " + spec.methods[m]);
      for (std::size_t s = 0; s < stats.size(); ++s)
        r.stats[m][s] = method_statistic(*mr, stats[s]);
    }
  } catch (const std::exception& e) {
    r.failed = true;
    r.message = text::one_line(e.what());
    if (r.message.empty()) r.message = "unknown error";
    for (auto& row : r.stats) std::fill(row.begin(), row.end(), kNaN);
  }
  return r;
}

}  // namespace arttrack::sim
