#include "arttrack/sim/tuning.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/sweep.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/tracker_config_yaml.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

// A path as a single-quoted YAML scalar.
std::string yaml_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

// Whether the tracker's configuration reads p.key as a whole number: it
// rejects a value halfway between two (ConfigNode::whole_number), before
// any range check. The parser says, so no list here goes stale.
bool takes_whole_numbers(const YamlDocument& base, TuningParameter p) {
  p.integer = false;
  try {
    candidate_document(base, {p}, {std::floor(p.lo) + 0.5});
  } catch (const InputError& e) {
    return std::string(e.what()).find("is not a whole number") != std::string::npos;
  }
  return false;
}

}  // namespace

// ---- parameters and objective ----

double TuningParameter::value_at(double u) const {
  const double v = lo + std::clamp(u, 0.0, 1.0) * (hi - lo);
  if (integer) return std::clamp(std::round(v), lo, hi);
  // The value written to YAML, exactly.
  return std::strtod(text::format_g(v, 10).c_str(), nullptr);
}

double TuningParameter::unit_of(double value) const {
  return std::clamp((value - lo) / (hi - lo), 0.0, 1.0);
}

std::string TuningParameter::text(double value) const {
  if (integer) return std::to_string((long long)std::llround(value));
  return text::format_g(value, 10);
}

std::vector<TuningParameter> parse_tuning_parameters(const std::vector<std::string>& specs,
                                                     const YamlDocument& base) {
  std::vector<TuningParameter> params;
  for (const std::string& joined : specs) {
    std::stringstream in(joined);
    for (std::string spec; std::getline(in, spec, ',');) {
      spec = text::trim(spec);
      const std::string context = "--params '" + spec + "'";
      if (spec.empty()) throw InputError("--params '" + joined + "': an empty parameter");
      const auto eq = spec.find('=');
      if (eq == std::string::npos || eq == 0)
        throw InputError(context + ": expected key=lo:hi (or key=lo:hi:int)");
      TuningParameter p;
      p.key = text::trim(spec.substr(0, eq));
      std::vector<std::string> parts;
      std::stringstream r(spec.substr(eq + 1));
      for (std::string part; std::getline(r, part, ':');) parts.push_back(text::trim(part));
      const bool typed = parts.size() == 3 && (parts[2] == "int" || parts[2] == "real");
      if (typed) {
        p.integer = parts[2] == "int";
        parts.pop_back();
      }
      if (parts.size() != 2) throw InputError(context + ": expected key=lo:hi (or key=lo:hi:int)");
      if (!text::parse_number(parts[0], p.lo))
        throw InputError(context + ": lo '" + parts[0] + "' is not a finite number");
      if (!text::parse_number(parts[1], p.hi))
        throw InputError(context + ": hi '" + parts[1] + "' is not a finite number");
      if (!(p.lo < p.hi)) throw InputError(context + ": lo must be below hi");
      if (!typed) p.integer = takes_whole_numbers(base, p);
      if (p.integer && (p.lo != std::floor(p.lo) || p.hi != std::floor(p.hi)))
        throw InputError(context + ": " + p.key + " takes whole numbers: give whole bounds");
      for (const TuningParameter& q : params)
        if (q.key == p.key) throw InputError(context + ": " + p.key + " is given twice");
      // Both ends must make a configuration the tracker accepts.
      for (double v : {p.lo, p.hi}) {
        try {
          candidate_document(base, {p}, {v});
        } catch (const InputError& e) {
          throw InputError(context + ": " + e.what());
        }
      }
      params.push_back(p);
    }
  }
  if (params.empty()) throw InputError("--params: give at least one key=lo:hi");
  return params;
}

std::string Objective::text() const {
  return std::string(aggregate == Aggregate::kMean ? "mean_" : "max_") + statistic;
}

Objective parse_objective(const std::string& text) {
  Objective o;
  std::string stat;
  if (text.rfind("mean_", 0) == 0) {
    o.aggregate = Objective::Aggregate::kMean;
    stat = text.substr(5);
  } else if (text.rfind("max_", 0) == 0) {
    o.aggregate = Objective::Aggregate::kMax;
    stat = text.substr(4);
  } else {
    throw InputError("--objective '" + text +
                     "': expected mean_STAT or max_STAT, e.g. mean_converged_p75_translation_m");
  }
  check_statistic_name(stat, "--objective '" + text + "'");
  o.statistic = stat;
  return o;
}

// ---- candidates ----

bool document_number(const YamlDocument& doc, const std::string& key, double& value) {
  const std::optional<YAML::Node> node = find_key(doc.root, key);
  return node && node->IsScalar() && text::parse_number(node->Scalar(), value);
}

YamlDocument candidate_document(const YamlDocument& base,
                                const std::vector<TuningParameter>& params,
                                const std::vector<double>& values) {
  YamlDocument doc{YAML::Clone(base.root), base.file};
  for (std::size_t i = 0; i < params.size(); ++i)
    apply_override(doc, params[i].key + "=" + params[i].text(values[i]));
  tracker_config_from_yaml(doc);  // throws InputError for a bad candidate
  return doc;
}

std::string tracker_yaml_text(const YamlDocument& doc, const std::string& comment) {
  std::ostringstream out;
  std::stringstream lines(comment);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  YAML::Emitter emit;
  emit << doc.root;
  out << emit.c_str() << "\n";
  return out.str();
}

// ---- evaluation ----

const std::vector<std::string>& outcome_statistics() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = sweep_statistics();
    n.push_back("p50_image_update_ms");
    return n;
  }();
  return names;
}

ScenarioOutcome evaluate_scenario(const Scenario& scenario, const fs::path& path,
                                  const YamlDocument* tracker, const Objective& objective, int runs,
                                  long long seed) {
  ScenarioOutcome o;
  o.scenario = path;
  o.name = path.stem().string();
  const auto& names = outcome_statistics();
  o.stats.assign(names.size(), kNaN);
  try {
    Scenario sc = scenario;
    if (tracker) set_tracker_document(sc, *tracker, tracker->file);
    o.name = sc.name;
    o.duration_s = sc.duration_s;
    RunOptions options;
    options.runs = runs;
    options.seed = seed;
    options.methods = {objective.method};
    options.frames_to_keep = 0;
    const ScenarioResult r = run_scenario(sc, options);
    o.seed = r.recipe.seed;
    const MethodResult* m = r.method(objective.method);
    if (!m) throw InputError("the runner returned no result for " + objective.method);
    for (std::size_t i = 0; i < names.size(); ++i) o.stats[i] = method_statistic(*m, names[i]);
    o.image_update_p50_ms =
        std::isfinite(m->timing.image_update_ms.p50) ? m->timing.image_update_ms.p50 : 0.0;
    const double v = method_statistic(*m, objective.statistic);
    if (std::isfinite(v))
      o.objective_statistic = v;
    else if (objective.statistic == "convergence_time_s")
      o.objective_statistic = o.duration_s;
  } catch (const std::exception& e) {
    o.failed = true;
    o.message = text::one_line(e.what());
    std::fill(o.stats.begin(), o.stats.end(), kNaN);
    o.objective_statistic = kFailedStatistic;
  }
  return o;
}

double objective_value(const Objective& objective, const std::vector<ScenarioOutcome>& outcomes) {
  if (outcomes.empty()) return kFailedStatistic;
  double agg = objective.aggregate == Objective::Aggregate::kMax
                   ? -std::numeric_limits<double>::infinity()
                   : 0.0;
  double ms = 0;
  for (const ScenarioOutcome& o : outcomes) {
    if (objective.aggregate == Objective::Aggregate::kMax)
      agg = std::max(agg, o.objective_statistic);
    else
      agg += o.objective_statistic;
    ms += o.image_update_p50_ms;
  }
  if (objective.aggregate == Objective::Aggregate::kMean) agg /= double(outcomes.size());
  return agg + objective.time_penalty_per_ms * ms / double(outcomes.size());
}

std::string seeds_text(const std::vector<ScenarioOutcome>& outcomes) {
  std::string s;
  for (const ScenarioOutcome& o : outcomes)
    s += (s.empty() ? "" : ", ") + o.name + " " + (o.failed ? "-" : std::to_string(o.seed));
  return s;
}

// ---- the search ----

namespace {

std::string values_text(const std::vector<TuningParameter>& params, const std::vector<double>& v) {
  std::string s;
  for (std::size_t i = 0; i < params.size(); ++i)
    s += (i ? " " : "") + params[i].key + "=" + params[i].text(v[i]);
  return s;
}

std::string eval_file_name(int index) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "eval_%04d.yaml", index);
  return buf;
}

void write_outputs(const TuningOptions& options, const TuningResult& result, bool final) {
  std::ostringstream csv;
  write_search_csv(csv, options, result);
  text::write_text(options.out_dir / "search.csv", csv.str());
  if (final) text::write_text(options.out_dir / "tuning.html", tuning_html(options, result));
}

}  // namespace

TuningResult tune(const TuningOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto log = [&](const std::string& s) {
    if (options.log) options.log(s);
  };
  if (options.scenarios.empty()) throw InputError("tune: name at least one scenario");
  if (options.budget < 1) throw InputError("--budget must be >= 1");
  if (options.runs < 0) throw InputError("--runs must be >= 1");
  if (options.seed < -1) throw InputError("--seed must be >= 0");
  if (!(options.objective.time_penalty_per_ms >= 0) ||
      !std::isfinite(options.objective.time_penalty_per_ms))
    throw InputError("--time-penalty must be a finite number >= 0");
  check_statistic_name(options.objective.statistic, "--objective");
  parse_method(options.objective.method, "--tracker-method");

  TuningResult result;
  const YamlDocument base = load_yaml_file(options.base_config.string());
  tracker_config_from_yaml(base);
  result.params = parse_tuning_parameters(options.parameter_specs, base);
  const std::vector<TuningParameter>& params = result.params;

  // Every scenario is loaded once, with the base configuration (candidates
  // replace it: evaluate_scenario); a key a scenario overrides itself cannot
  // be tuned on it.
  std::vector<fs::path> all = options.scenarios;
  all.insert(all.end(), options.validation.begin(), options.validation.end());
  std::vector<Scenario> loaded;
  for (const fs::path& s : all) {
    std::vector<std::string> ov = options.scenario_overrides;
    ov.push_back("tracker=" + yaml_quoted(fs::absolute(options.base_config).string()));
    loaded.push_back(load_scenario(s, ov));
    const YamlDocument doc = load_yaml_file(s.string());
    const YAML::Node over = doc.root["tracker_overrides"];
    if (over && over.IsMap())
      for (const auto& kv : over)
        for (const TuningParameter& p : params)
          if (kv.first.as<std::string>() == p.key)
            log("warning: " + s.string() + " sets tracker_overrides." + p.key +
                " itself: tuning it has no effect on this scenario");
  }

  std::error_code ec;
  fs::create_directories(options.out_dir / "candidates", ec);
  if (ec) throw InputError(options.out_dir.string() + ": cannot create folder: " + ec.message());

  std::vector<double> u0;
  for (const TuningParameter& p : params) {
    double v = kNaN;
    if (!document_number(base, p.key, v)) v = kNaN;
    result.default_values.push_back(v);
    u0.push_back(std::isnan(v) ? 0.5 : p.unit_of(v));
  }

  std::map<std::string, std::size_t> seen;  // values text -> history index
  auto f = [&](const std::vector<double>& u) {
    Evaluation ev;
    ev.index = int(result.history.size()) + 1;
    for (std::size_t i = 0; i < params.size(); ++i) ev.values.push_back(params[i].value_at(u[i]));
    const std::string key = values_text(params, ev.values);
    const auto it = seen.find(key);
    if (it != seen.end()) {
      ev.outcomes = result.history[it->second].outcomes;
      ev.objective = result.history[it->second].objective;
      ev.cached = true;
    } else {
      // The candidate, named in messages by the file that records it (not
      // read back).
      YamlDocument doc = candidate_document(base, params, ev.values);
      doc.file = fs::absolute(options.out_dir / "candidates" / eval_file_name(ev.index)).string();
      text::write_text(doc.file, tracker_yaml_text(doc, "arttrack tune candidate " +
                                                            std::to_string(ev.index) + ": " + key));
      for (std::size_t i = 0; i < options.scenarios.size(); ++i)
        ev.outcomes.push_back(evaluate_scenario(loaded[i], options.scenarios[i], &doc,
                                                options.objective, options.runs, options.seed));
      ev.objective = objective_value(options.objective, ev.outcomes);
      seen[key] = result.history.size();
    }
    result.history.push_back(ev);
    double best = ev.objective;
    for (const Evaluation& e : result.history) best = std::min(best, e.objective);
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    const double left = elapsed / ev.index * (options.budget - ev.index);
    std::string failed;
    for (const ScenarioOutcome& o : ev.outcomes)
      if (o.failed) failed += " [" + o.name + " failed: " + o.message + "]";
    log("evaluation " + std::to_string(ev.index) + "/" + std::to_string(options.budget) + ": " +
        key + " -> " + text::format_g(ev.objective, 6) + (ev.cached ? " (same as before)" : "") +
        " (best " + text::format_g(best, 6) + "; " + text::format_g(elapsed, 3) + " s, at most " +
        text::format_g(left, 3) + " s left)" + failed);
    write_outputs(options, result, false);
    return ev.objective;
  };
  result.optimizer = minimize_unit_box(f, u0, options.optimizer, options.budget);
  result.best = 0;
  for (std::size_t i = 1; i < result.history.size(); ++i)
    if (result.history[i].objective < result.history[result.best].objective) result.best = i;
  const Evaluation& best = result.history[result.best];
  result.tuned = candidate_document(base, params, best.values);
  const fs::path tuned_file = options.out_dir / "tuned.yaml";
  text::write_text(
      tuned_file,
      tracker_yaml_text(
          result.tuned,
          "Tracker configuration tuned by arttrack tune (" +
              std::string(optimizer_name(options.optimizer)) + ", " +
              std::to_string(result.history.size()) + " evaluations)\n" +
              "base: " + options.base_config.string() + "\n" + "objective " +
              options.objective.text() + " of " + options.objective.method + ": " +
              text::format_g(best.objective, 6) + " (evaluation " + std::to_string(best.index) +
              ")\n" + "scenario seeds" + (options.seed >= 0 ? " (--seed)" : "") + ": " +
              seeds_text(best.outcomes) + "\n" + "tuned: " + values_text(params, best.values)));

  // Default against tuned on every scenario.
  const YamlDocument tuned{result.tuned.root, fs::absolute(tuned_file).string()};
  for (std::size_t i = 0; i < all.size(); ++i) {
    const bool validation = i >= options.scenarios.size();
    result.compare_is_validation.push_back(validation);
    result.compare_default.push_back(evaluate_scenario(
        loaded[i], all[i], nullptr, options.objective, options.runs, options.seed));
    result.compare_tuned.push_back(validation ? evaluate_scenario(loaded[i], all[i], &tuned,
                                                                  options.objective, options.runs,
                                                                  options.seed)
                                              : best.outcomes[i]);
    log(std::string(validation ? "validation " : "tuning ") + result.compare_default.back().name +
        ": " + options.objective.statistic + " default " +
        text::format_g(result.compare_default.back().objective_statistic, 6) + ", tuned " +
        text::format_g(result.compare_tuned.back().objective_statistic, 6));
  }
  write_outputs(options, result, true);
  return result;
}

// ---- outputs ----

void write_search_csv(std::ostream& out, const TuningOptions& options, const TuningResult& result) {
  out << "evaluation";
  for (const TuningParameter& p : result.params) out << ',' << text::csv_field(p.key);
  out << ",objective,cached";
  std::vector<std::string> names;
  for (const fs::path& s : options.scenarios) {
    std::string n = s.stem().string();
    int k = 2;
    while (std::find(names.begin(), names.end(), n) != names.end())
      n = s.stem().string() + "#" + std::to_string(k++);
    names.push_back(n);
  }
  for (const std::string& n : names)
    out << ',' << text::csv_field(n + ":" + options.objective.statistic) << ','
        << text::csv_field(n + ":p50_image_update_ms");
  out << ",status\n";
  for (const Evaluation& e : result.history) {
    out << e.index;
    for (std::size_t i = 0; i < e.values.size(); ++i)
      out << ',' << result.params[i].text(e.values[i]);
    out << ',' << text::csv_number(e.objective) << ',' << (e.cached ? 1 : 0);
    std::string status;
    for (const ScenarioOutcome& o : e.outcomes) {
      out << ',' << text::csv_number(o.objective_statistic) << ','
          << text::csv_number(o.image_update_p50_ms);
      if (o.failed) status += (status.empty() ? "" : "; ") + o.name + ": " + o.message;
    }
    out << ',' << text::csv_field(status.empty() ? "ok" : status) << '\n';
  }
}

}  // namespace arttrack::sim
