// Tuning tracker parameters (`arttrack tune`): derivative-free minimisation
// (NLopt: BOBYQA, COBYLA, Nelder-Mead, DIRECT-L) of a statistic of the
// tracking errors over several scenarios at once, in coordinates normalised
// to [0, 1] per parameter.
//
// A candidate is the base tracker configuration (a YAML file) with one
// `key=value` override per parameter, built in memory and recorded in
// DIR/candidates/. Each scenario is loaded once, with the base configuration;
// a candidate becomes its tracker configuration (set_tracker_document: the
// scenario's own `tracker_overrides` still apply on top). Every candidate
// runs every scenario with the same seeds (the scenario's own, or
// TuningOptions::seed), so candidates meet the same simulated data (common
// random numbers).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "arttrack/sim/scenario.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {

// ---- the optimiser ----

enum class Optimizer { kBobyqa, kCobyla, kNelderMead, kDirect };

// "bobyqa", "cobyla", "neldermead", "direct" (tune --optimizer); InputError
// naming --optimizer otherwise.
Optimizer parse_optimizer(const std::string& name);
const char* optimizer_name(Optimizer optimizer);

struct OptimizerResult {
  std::vector<double> u;  // best point found, in [0, 1]^n
  double value = 0;       // f there
  int evaluations = 0;    // calls of f
  std::string stop;       // why NLopt stopped
};

// Minimises f over the unit box [0, 1]^n from u0 with at most `budget`
// calls of f (local methods start with steps of 0.25 and stop when a step
// is below `tolerance`; DIRECT-L ignores u0). f may throw: the search stops
// and the exception propagates. NLopt's random seed is fixed: same f, same
// calls.
OptimizerResult minimize_unit_box(const std::function<double(const std::vector<double>&)>& f,
                                  const std::vector<double>& u0, Optimizer optimizer, int budget,
                                  double tolerance = 1e-4);

// ---- parameters and objective ----

// One tuned tracker key and its interval.
struct TuningParameter {
  std::string key;  // dotted tracker YAML key, e.g. depth_model.occlusion_prior
  double lo = 0, hi = 1;
  // Whole numbers only (rounded): the keys the tracker's configuration reads
  // as whole numbers (particle_filter.particles, depth_model.width, ...), or
  // `:int`; `:real` makes any key real.
  bool integer = false;

  // The value at normalised u (clamped into [0, 1]), rounded as text()
  // writes it: to a whole number or to 10 significant digits.
  double value_at(double u) const;
  // The normalised coordinate of a value, clamped into [0, 1].
  double unit_of(double value) const;
  // The value as YAML text (`%.10g`, whole numbers without a point).
  std::string text(double value) const;
};

// Parses `key=lo:hi[:int]` specs; each may hold several separated by
// commas. Every key must be one the tracker configuration reads, and lo and
// hi values it accepts (checked by loading `base` with each); lo < hi. Errors
// name the spec.
std::vector<TuningParameter> parse_tuning_parameters(const std::vector<std::string>& specs,
                                                     const YamlDocument& base);

// What is minimised: an aggregate over scenarios of one statistic of one
// method (sweep.h's method_statistic names), plus time_penalty_per_ms times
// the mean over scenarios of the p50 image update time (ms, wall time).
struct Objective {
  enum class Aggregate { kMean, kMax };
  Aggregate aggregate = Aggregate::kMean;
  std::string statistic = "converged_p75_translation_m";
  std::string method = "full_fusion";
  double time_penalty_per_ms = 0;
  // As given: mean_converged_p75_translation_m.
  std::string text() const;
};

// Parses `mean_STAT` or `max_STAT`, e.g. mean_converged_p75_translation_m;
// InputError naming the text otherwise.
Objective parse_objective(const std::string& text);

// A scenario statistic that is not finite (or a run that failed) counts as
// this much, except convergence_time_s, where never counts as the duration.
constexpr double kFailedStatistic = 1000.0;

// ---- evaluating candidates ----

// One scenario run with one tracker configuration.
struct ScenarioOutcome {
  std::filesystem::path scenario;
  std::string name;
  double duration_s = 0;
  bool failed = false;
  std::string message;  // why it failed, one line
  // The scenario seed its runs' seeds derived from (0 if it failed to load).
  std::uint64_t seed = 0;
  // The method's sweep_statistics() in order, then p50_image_update_ms.
  std::vector<double> stats;
  // The objective's statistic, made finite (kFailedStatistic / duration).
  double objective_statistic = kFailedStatistic;
  double image_update_p50_ms = 0;
};

// Statistic names of ScenarioOutcome::stats.
const std::vector<std::string>& outcome_statistics();

// Runs `scenario` (loaded from the file `path`) with the tracker
// configuration `tracker` (a document named by its file, as
// set_tracker_document takes it; null: the scenario's own configuration),
// only the objective's method, `runs` runs (0: the scenario's), from scenario
// seed `seed` (-1: the scenario's). Failures, a candidate the tracker
// refuses among them, are recorded, not thrown.
ScenarioOutcome evaluate_scenario(const Scenario& scenario, const std::filesystem::path& path,
                                  const YamlDocument* tracker, const Objective& objective, int runs,
                                  long long seed = -1);

// The objective over scenario outcomes.
double objective_value(const Objective& objective, const std::vector<ScenarioOutcome>& outcomes);

// The scenario seed of each outcome, "-" for a failed one: "default 1,
// noisy_camera 1".
std::string seeds_text(const std::vector<ScenarioOutcome>& outcomes);

// The base document with each parameter set to its value (checked: the
// result loads as a tracker configuration, else InputError).
YamlDocument candidate_document(const YamlDocument& base,
                                const std::vector<TuningParameter>& params,
                                const std::vector<double>& values);

// A configuration document as YAML text (block style) after `comment`
// lines (each prefixed with "# ").
std::string tracker_yaml_text(const YamlDocument& doc, const std::string& comment);

// The value at a key path (`a.b[1].c`, as apply_override takes it) in a
// document, if it is a number.
bool document_number(const YamlDocument& doc, const std::string& key, double& value);

// ---- the search ----

struct TuningOptions {
  std::vector<std::filesystem::path> scenarios;   // tuned on
  std::vector<std::filesystem::path> validation;  // only compared at the end
  std::vector<std::string> scenario_overrides;    // --set, for every scenario
  std::filesystem::path base_config;              // tracker YAML
  std::vector<std::string> parameter_specs;       // --params
  Objective objective;
  Optimizer optimizer = Optimizer::kBobyqa;
  int budget = 30;      // objective evaluations
  int runs = 0;         // per scenario (0: each scenario's)
  long long seed = -1;  // scenario seed of every scenario (-1: each scenario's own)
  std::filesystem::path out_dir;
  // Told after each evaluation and each final comparison run (may be empty).
  std::function<void(const std::string&)> log;
};

// One candidate evaluated during the search.
struct Evaluation {
  int index = 0;                          // 1-based
  std::vector<double> values;             // per parameter
  std::vector<ScenarioOutcome> outcomes;  // per tuning scenario
  double objective = 0;
  bool cached = false;  // same values as an earlier candidate: not re-run
};

struct TuningResult {
  std::vector<TuningParameter> params;
  std::vector<double> default_values;  // base values (NaN if the base lacks the key)
  std::vector<Evaluation> history;
  std::size_t best = 0;  // index into history
  OptimizerResult optimizer;
  YamlDocument tuned;
  // Final comparison on tuning then validation scenarios: default vs tuned.
  std::vector<ScenarioOutcome> compare_default, compare_tuned;
  std::vector<bool> compare_is_validation;
};

// Checks the options (scenarios load, parameters, objective), runs the
// search, then compares default and tuned on every scenario. Writes
// DIR/candidates/, DIR/tuned.yaml, DIR/search.csv and DIR/tuning.html.
TuningResult tune(const TuningOptions& options);

// search.csv: evaluation, one column per parameter, objective, cached, per
// tuning scenario its objective statistic and p50 image update ms, status.
void write_search_csv(std::ostream& out, const TuningOptions& options, const TuningResult& result);

// tuning.html: self-contained; the parameters (interval, default, tuned),
// the search (objective per evaluation and the best so far, in the
// statistic's unit), and per scenario a table of the statistics and a bar
// chart, default against tuned. Wall times (image update) are shown, never
// marked better or worse: they vary from run to run.
std::string tuning_html(const TuningOptions& options, const TuningResult& result);

}  // namespace arttrack::sim
