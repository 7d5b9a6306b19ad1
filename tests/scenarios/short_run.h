// Short, cheap runs of the shipped scenarios for the slow test suite: the
// scenario file as it is, shortened and cheapened through overrides (a
// 160x120 camera, the tracker's 80x60 likelihood, one run with the file's
// seed), and windowed statistics of the results.
//
// Every run also takes the overrides in the environment variable
// ARTTRACK_SCENARIO_TEST_SET (';'-separated `key=value`, as `arttrack run
// --set`), so a deliberately broken configuration can be checked to fail the
// thresholds, e.g.
//   ARTTRACK_SCENARIO_TEST_SET='camera.drop_probability=0.99'   (almost no images)
//   ARTTRACK_SCENARIO_TEST_SET='tracker_overrides={particle_filter.particles: 1}'
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "arttrack/sim/run_outputs.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/scoring.h"
#include "arttrack/tracker/units.h"

namespace arttrack::sim::test {

constexpr double kMm = 1e-3;

// A shipped scenario: scenarios/<relative>.yaml in the source tree.
inline std::filesystem::path scenario_file(const std::string& relative) {
  return std::filesystem::path(ARTTRACK_SOURCE_DIR) / "scenarios" / (relative + ".yaml");
}

// Overrides from ARTTRACK_SCENARIO_TEST_SET.
inline std::vector<std::string> environment_overrides() {
  std::vector<std::string> out;
  const char* text = std::getenv("ARTTRACK_SCENARIO_TEST_SET");
  if (text == nullptr) return out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ';');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// One run of scenarios/<relative>.yaml for `duration_s` with the given
// methods, a 160x120 camera, the 80x60 likelihood, then `overrides`, then the
// environment's; prints the summary table.
inline ScenarioResult run_short(const std::string& relative, double duration_s,
                                const std::vector<std::string>& methods,
                                std::vector<std::string> overrides = {}) {
  std::ostringstream duration;
  duration << "duration_s=" << duration_s;
  overrides.insert(overrides.begin(),
                   {duration.str(), "camera.width=160", "camera.height=120",
                    "tracker_overrides={depth_model.width: 80, depth_model.height: 60}"});
  for (const std::string& o : environment_overrides()) overrides.push_back(o);
  const Scenario scenario = load_scenario(scenario_file(relative), overrides);
  RunOptions options;
  options.runs = 1;
  options.methods = methods;
  options.frames_to_keep = 0;
  ScenarioResult result = run_scenario(scenario, options);
  print_summary_table(std::cout, result);
  return result;
}

inline const MethodResult& method(const ScenarioResult& r, const std::string& name) {
  const MethodResult* m = r.method(name);
  if (m == nullptr) throw std::runtime_error("no results for method " + name);
  return *m;
}

// Percentiles of a method's end-effector translation error over the samples
// with time in [from_s, to_s], pooled over runs; printed.
inline Percentiles window(const ScenarioResult& r, const std::string& name, double from_s,
                          double to_s) {
  std::vector<double> values;
  for (const ErrorTrace& run : method(r, name).scores.runs())
    for (std::size_t i = 0; i < run.size(); ++i)
      if (run.time_s()[i] >= from_s && run.time_s()[i] <= to_s)
        values.push_back(run.translation_m()[i]);
  const Percentiles p = percentiles(values);
  std::cout << name << " from " << from_s << " to " << to_s << " s: p1 " << p.p01 / kMm
            << " mm, p50 " << p.p50 / kMm << " mm, p99 " << p.p99 / kMm << " mm\n";
  return p;
}

// Percentiles of the end-effector translation error over every sample, and
// over the converged ones (time >= scoring.converged_after_s).
inline const Percentiles& all(const ScenarioResult& r, const std::string& name) {
  return method(r, name).summary.all.translation_m;
}
inline const Percentiles& converged(const ScenarioResult& r, const std::string& name) {
  return method(r, name).summary.converged.translation_m;
}

// Index of a joint in the result's per-joint vectors.
inline std::size_t joint_index(const ScenarioResult& r, const std::string& joint) {
  for (std::size_t j = 0; j < r.joint_names.size(); ++j)
    if (r.joint_names[j] == joint) return j;
  throw std::runtime_error("no joint " + joint);
}

}  // namespace arttrack::sim::test
