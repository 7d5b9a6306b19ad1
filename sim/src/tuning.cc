#include "arttrack/sim/tuning.h"

#include <yaml-cpp/yaml.h>
#include <nlopt.hpp>

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
#include <set>
#include <sstream>

#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/sweep.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "text_format.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A path as a single-quoted YAML scalar.
std::string yaml_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

bool is_integer_key(const std::string& key) {
  static const std::set<std::string> keys = {"particle_filter.particles", "depth_model.width",
                                             "depth_model.height", "timing.buffer_capacity",
                                             "timing.max_pending_images"};
  return keys.count(key) > 0;
}

}  // namespace

// ---- optimiser ----

Optimizer parse_optimizer(const std::string& name) {
  if (name == "bobyqa") return Optimizer::kBobyqa;
  if (name == "cobyla") return Optimizer::kCobyla;
  if (name == "neldermead") return Optimizer::kNelderMead;
  if (name == "direct") return Optimizer::kDirect;
  throw InputError("--optimizer '" + name + "': expected bobyqa, cobyla, neldermead or direct");
}

const char* optimizer_name(Optimizer o) {
  switch (o) {
    case Optimizer::kBobyqa:
      return "bobyqa";
    case Optimizer::kCobyla:
      return "cobyla";
    case Optimizer::kNelderMead:
      return "neldermead";
    case Optimizer::kDirect:
      return "direct";
  }
  return "?";
}

namespace {

struct SearchContext {
  const std::function<double(const std::vector<double>&)>* f = nullptr;
  int budget = 0;
  int calls = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_u;
  std::exception_ptr error;
  bool budget_spent = false;
};

double nlopt_objective(unsigned n, const double* x, double* /*grad*/, void* data) {
  auto* ctx = static_cast<SearchContext*>(data);
  if (ctx->calls >= ctx->budget) {
    ctx->budget_spent = true;
    throw nlopt::forced_stop();
  }
  std::vector<double> u(x, x + n);
  for (double& v : u) v = std::clamp(v, 0.0, 1.0);
  double value = 0;
  try {
    value = (*ctx->f)(u);
  } catch (...) {
    ctx->error = std::current_exception();
    throw nlopt::forced_stop();
  }
  ++ctx->calls;
  if (value < ctx->best || ctx->best_u.empty()) {
    ctx->best = value;
    ctx->best_u = u;
  }
  return value;
}

std::string stop_text(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS:
      return "converged";
    case nlopt::STOPVAL_REACHED:
      return "target value reached";
    case nlopt::FTOL_REACHED:
      return "objective changes below tolerance";
    case nlopt::XTOL_REACHED:
      return "steps below tolerance";
    case nlopt::MAXEVAL_REACHED:
      return "budget spent";
    case nlopt::MAXTIME_REACHED:
      return "time limit";
    default:
      return "stopped (code " + std::to_string(int(r)) + ")";
  }
}

}  // namespace

OptimizerResult minimize_unit_box(const std::function<double(const std::vector<double>&)>& f,
                                  const std::vector<double>& u0, Optimizer optimizer, int budget,
                                  double tolerance) {
  const unsigned n = unsigned(u0.size());
  if (n == 0) throw InputError("tune: no parameters to optimise");
  if (budget < 1) throw InputError("--budget must be >= 1");
  nlopt::algorithm alg = nlopt::LN_BOBYQA;
  switch (optimizer) {
    case Optimizer::kBobyqa:
      alg = nlopt::LN_BOBYQA;
      break;
    case Optimizer::kCobyla:
      alg = nlopt::LN_COBYLA;
      break;
    case Optimizer::kNelderMead:
      alg = nlopt::LN_NELDERMEAD;
      break;
    case Optimizer::kDirect:
      alg = nlopt::GN_DIRECT_L;
      break;
  }
  nlopt::srand(20170101);  // deterministic, whatever the algorithm
  nlopt::opt opt(alg, n);
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(budget);
  opt.set_xtol_abs(tolerance);
  if (optimizer != Optimizer::kDirect) opt.set_initial_step(0.25);

  SearchContext ctx;
  ctx.f = &f;
  ctx.budget = budget;
  opt.set_min_objective(nlopt_objective, &ctx);
  std::vector<double> x(n);
  for (unsigned i = 0; i < n; ++i) x[i] = std::clamp(u0[i], 0.0, 1.0);
  OptimizerResult result;
  double value = 0;
  try {
    result.stop = stop_text(opt.optimize(x, value));
  } catch (const nlopt::forced_stop&) {
    if (ctx.error) std::rethrow_exception(ctx.error);
    result.stop = ctx.budget_spent ? "budget spent" : "forced stop";
  } catch (const nlopt::roundoff_limited&) {
    result.stop = "roundoff limited";
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("optimiser: invalid arguments: ") + e.what());
  } catch (const std::runtime_error& e) {
    if (ctx.error) std::rethrow_exception(ctx.error);
    result.stop = std::string("optimiser failure: ") + e.what();
  }
  if (ctx.error) std::rethrow_exception(ctx.error);
  result.evaluations = ctx.calls;
  result.u = ctx.best_u.empty() ? x : ctx.best_u;
  result.value = ctx.best;
  return result;
}

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
      if (parts.size() == 3 && parts[2] == "int") {
        p.integer = true;
        parts.pop_back();
      } else if (parts.size() == 3 && parts[2] == "real") {
        parts.pop_back();
      } else {
        p.integer = is_integer_key(p.key);
      }
      if (parts.size() != 2) throw InputError(context + ": expected key=lo:hi (or key=lo:hi:int)");
      if (!text::parse_number(parts[0], p.lo))
        throw InputError(context + ": lo '" + parts[0] + "' is not a finite number");
      if (!text::parse_number(parts[1], p.hi))
        throw InputError(context + ": hi '" + parts[1] + "' is not a finite number");
      if (!(p.lo < p.hi)) throw InputError(context + ": lo must be below hi");
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

ScenarioOutcome evaluate_scenario(const fs::path& scenario,
                                  const std::vector<std::string>& overrides,
                                  const fs::path& tracker_file, const Objective& objective,
                                  int runs, long long seed) {
  ScenarioOutcome o;
  o.scenario = scenario;
  o.name = scenario.stem().string();
  const auto& names = outcome_statistics();
  o.stats.assign(names.size(), kNaN);
  try {
    std::vector<std::string> all = overrides;
    all.push_back("tracker=" + yaml_quoted(fs::absolute(tracker_file).string()));
    const Scenario sc = load_scenario(scenario, all);
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

// ---- the search ----

namespace {

std::string values_text(const std::vector<TuningParameter>& params, const std::vector<double>& v) {
  std::string s;
  for (std::size_t i = 0; i < params.size(); ++i)
    s += (i ? " " : "") + params[i].key + "=" + params[i].text(v[i]);
  return s;
}

// The scenario seed of each outcome: "default 1, noisy_camera 1".
std::string seeds_text(const std::vector<ScenarioOutcome>& outcomes) {
  std::string s;
  for (const ScenarioOutcome& o : outcomes)
    s += (s.empty() ? "" : ", ") + o.name + " " + (o.failed ? "-" : std::to_string(o.seed));
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

  // Every scenario must load with the base configuration; a key a scenario
  // overrides itself cannot be tuned on it.
  std::vector<fs::path> all = options.scenarios;
  all.insert(all.end(), options.validation.begin(), options.validation.end());
  for (const fs::path& s : all) {
    std::vector<std::string> ov = options.scenario_overrides;
    ov.push_back("tracker=" + yaml_quoted(fs::absolute(options.base_config).string()));
    load_scenario(s, ov);
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
      const fs::path file = options.out_dir / "candidates" / eval_file_name(ev.index);
      const YamlDocument doc = candidate_document(base, params, ev.values);
      text::write_text(file, tracker_yaml_text(doc, "arttrack tune candidate " +
                                                        std::to_string(ev.index) + ": " + key));
      for (const fs::path& s : options.scenarios)
        ev.outcomes.push_back(evaluate_scenario(s, options.scenario_overrides, file,
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
  for (std::size_t i = 0; i < all.size(); ++i) {
    const bool validation = i >= options.scenarios.size();
    result.compare_is_validation.push_back(validation);
    result.compare_default.push_back(evaluate_scenario(all[i], options.scenario_overrides,
                                                       options.base_config, options.objective,
                                                       options.runs, options.seed));
    result.compare_tuned.push_back(
        validation ? evaluate_scenario(all[i], options.scenario_overrides, tuned_file,
                                       options.objective, options.runs, options.seed)
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

namespace {

struct Shown {
  std::string stat;
  std::string label;
  double scale;
  std::string unit;
};

const std::vector<Shown>& shown_stats() {
  static const std::vector<Shown> s = {
      {"p50_translation_m", "translation p50", 1e3, "mm"},
      {"p99_translation_m", "translation p99", 1e3, "mm"},
      {"converged_p50_translation_m", "converged translation p50", 1e3, "mm"},
      {"converged_p75_translation_m", "converged translation p75", 1e3, "mm"},
      {"converged_p99_translation_m", "converged translation p99", 1e3, "mm"},
      {"converged_p50_rotation_rad", "converged rotation p50", 180 / M_PI, "deg"},
      {"convergence_time_s", "convergence time", 1, "s"},
      {"p50_image_update_ms", "image update p50", 1, "ms"},
  };
  return s;
}

double outcome_stat(const ScenarioOutcome& o, const std::string& name) {
  const auto& names = outcome_statistics();
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? kNaN : o.stats[std::size_t(it - names.begin())];
}

std::string show(double v) {
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return "never";
  return text::format_g(v, 4);
}

std::string change(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b) || a == 0) return "";
  const double pct = 100 * (b - a) / a;
  return (pct > 0 ? "+" : "") + text::format_g(pct, 3) + "%";
}

// Grouped bars of the translation statistics, default (grey) vs tuned (blue).
void bar_chart(std::ostream& o, const ScenarioOutcome& d, const ScenarioOutcome& t) {
  std::vector<const Shown*> bars;
  for (const Shown& s : shown_stats())
    if (s.unit == "mm") bars.push_back(&s);
  double top = 0;
  for (const Shown* s : bars)
    for (const ScenarioOutcome* x : {&d, &t}) {
      const double v = outcome_stat(*x, s->stat) * s->scale;
      if (std::isfinite(v)) top = std::max(top, v);
    }
  if (top <= 0) top = 1;
  const double W = 560, H = 190, left = 44, bottom = 36, plot_h = H - bottom - 10;
  const double group = (W - left - 10) / double(bars.size());
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"10\">";
  o << "<line x1=\"" << left << "\" y1=\"10\" x2=\"" << left << "\" y2=\"" << 10 + plot_h
    << "\" stroke=\"#888\"/><text x=\"" << left - 4 << "\" y=\"14\" text-anchor=\"end\">"
    << text::format_g(top, 3) << "</text><text x=\"" << left - 4 << "\" y=\"" << 10 + plot_h
    << "\" text-anchor=\"end\">0</text><text x=\"4\" y=\"" << 10 + plot_h / 2 << "\">mm</text>";
  for (std::size_t i = 0; i < bars.size(); ++i) {
    const double gx = left + group * double(i);
    int k = 0;
    for (const ScenarioOutcome* x : {&d, &t}) {
      const double v = outcome_stat(*x, bars[i]->stat) * bars[i]->scale;
      const double h = std::isfinite(v) ? std::min(v / top, 1.0) * plot_h : 0;
      const double bx = gx + 6 + k * (group - 12) / 2;
      o << "<rect x=\"" << bx << "\" y=\"" << 10 + plot_h - h << "\" width=\"" << (group - 14) / 2
        << "\" height=\"" << h << "\" fill=\"" << (k == 0 ? "#999" : "#1f77b4") << "\"><title>"
        << (k == 0 ? "default " : "tuned ") << text::html_escape(bars[i]->label) << ": " << show(v)
        << " mm</title></rect>";
      ++k;
    }
    o << "<text x=\"" << gx + group / 2 << "\" y=\"" << H - bottom + 14
      << "\" text-anchor=\"middle\">"
      << text::html_escape(bars[i]->label.substr(0, bars[i]->label.find(' ')))
      << "</text><text x=\"" << gx + group / 2 << "\" y=\"" << H - bottom + 26
      << "\" text-anchor=\"middle\">"
      << text::html_escape(bars[i]->label.substr(bars[i]->label.find(' ') + 1)) << "</text>";
  }
  o << "</svg>";
}

// Objective per evaluation (dots) and best so far (line).
void search_chart(std::ostream& o, const TuningResult& r) {
  const double W = 560, H = 200, left = 60, bottom = 28, top_m = 10;
  std::vector<double> v;
  for (const Evaluation& e : r.history) v.push_back(e.objective);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double x : v)
    if (x < kFailedStatistic) {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  if (!(lo <= hi)) lo = 0, hi = 1;
  if (hi == lo) hi = lo + (lo == 0 ? 1 : std::fabs(lo) * 0.1);
  const double n = std::max<double>(1, double(v.size()) - 1);
  auto X = [&](std::size_t i) { return left + (W - left - 10) * double(i) / n; };
  // Logarithmic when the values span more than a factor 4 (a bad candidate
  // would flatten the rest).
  const bool log_y = lo > 0 && hi / lo > 4;
  auto Y = [&](double x) {
    x = std::clamp(x, lo, hi);
    const double t = log_y ? std::log(x / lo) / std::log(hi / lo) : (x - lo) / (hi - lo);
    return top_m + (H - bottom - top_m) * (1 - t);
  };
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"10\"><rect x=\"" << left << "\" y=\"" << top_m
    << "\" width=\"" << W - left - 10 << "\" height=\"" << H - bottom - top_m
    << "\" fill=\"none\" stroke=\"#ccc\"/><text x=\"" << left - 4 << "\" y=\"" << top_m + 8
    << "\" text-anchor=\"end\">" << text::format_g(hi, 3) << "</text><text x=\"" << left - 4
    << "\" y=\"" << H - bottom << "\" text-anchor=\"end\">" << text::format_g(lo, 3)
    << "</text><text x=\"" << (W + left) / 2 << "\" y=\"" << H - 6
    << "\" text-anchor=\"middle\">evaluation" << (log_y ? " (objective on a log scale)" : "")
    << "</text>";
  std::string line;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < v.size(); ++i) {
    best = std::min(best, v[i]);
    line += (i ? " L" : "M") + text::format_g(X(i), 6) + " " + text::format_g(Y(best), 6);
    o << "<circle cx=\"" << X(i) << "\" cy=\"" << Y(v[i]) << "\" r=\"3\" fill=\""
      << (i == r.best ? "#d62728" : "#1f77b4") << "\"><title>evaluation " << i + 1 << ": "
      << text::format_g(v[i], 6) << "</title></circle>";
  }
  o << "<path d=\"" << line << "\" fill=\"none\" stroke=\"#2ca02c\" stroke-width=\"1.5\"/></svg>";
}

}  // namespace

std::string tuning_html(const TuningOptions& options, const TuningResult& r) {
  std::ostringstream o;
  const Evaluation& best = r.history.at(r.best);
  o << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Tuning</title><style>"
    << "body{font-family:sans-serif;margin:1.5em;max-width:1100px}table{border-collapse:collapse;"
       "margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 8px;font-size:13px}"
       "td.n{text-align:right}.better{color:#070}.worse{color:#b00}"
    << "</style></head><body>\n<h1>Tuning: " << text::html_escape(options.objective.text())
    << " of " << text::html_escape(options.objective.method) << "</h1>\n<p>";
  o << "Minimised: the "
    << (options.objective.aggregate == Objective::Aggregate::kMean ? "mean" : "maximum")
    << " over the tuning scenarios of <code>" << text::html_escape(options.objective.statistic)
    << "</code>";
  if (options.objective.time_penalty_per_ms > 0)
    o << " plus " << text::format_g(options.objective.time_penalty_per_ms, 6)
      << " per ms of the mean p50 image update time";
  o << ". Optimiser " << optimizer_name(options.optimizer) << ", budget " << options.budget << ", "
    << r.history.size() << " evaluations (" << text::html_escape(r.optimizer.stop)
    << "); base configuration <code>" << text::html_escape(options.base_config.string())
    << "</code>; scenario seeds" << (options.seed >= 0 ? " (--seed)" : "") << ": "
    << text::html_escape(seeds_text(r.compare_default)) << ". Best: evaluation " << best.index
    << ", objective " << text::format_g(best.objective, 6)
    << ".</p>\n<h2>Parameters</h2>\n<table><tr><th>key</th><th>interval</th><th>default</th>"
       "<th>tuned</th></tr>\n";
  for (std::size_t i = 0; i < r.params.size(); ++i) {
    const TuningParameter& p = r.params[i];
    o << "<tr><td><code>" << text::html_escape(p.key) << "</code></td><td>[" << p.text(p.lo) << ", "
      << p.text(p.hi) << "]" << (p.integer ? " whole" : "") << "</td><td class=\"n\">"
      << (std::isnan(r.default_values[i]) ? "-" : text::format_g(r.default_values[i], 6))
      << "</td><td class=\"n\"><b>" << p.text(best.values[i]) << "</b></td></tr>\n";
  }
  o << "</table>\n<h2>Search</h2>\n";
  search_chart(o, r);
  o << "\n<h2>Default against tuned</h2>\n<table><tr><th>scenario</th><th>role</th><th>"
    << text::html_escape(options.objective.statistic)
    << " default</th><th>tuned</th><th>change</th></tr>\n";
  for (std::size_t i = 0; i < r.compare_default.size(); ++i) {
    const double a = r.compare_default[i].objective_statistic,
                 b = r.compare_tuned[i].objective_statistic;
    o << "<tr><td>" << text::html_escape(r.compare_default[i].name) << "</td><td>"
      << (r.compare_is_validation[i] ? "validation" : "tuning") << "</td><td class=\"n\">"
      << show(a) << "</td><td class=\"n\">" << show(b) << "</td><td class=\"n "
      << (b < a   ? "better"
          : b > a ? "worse"
                  : "")
      << "\">" << change(a, b) << "</td></tr>\n";
  }
  o << "</table>\n<p>Bars: grey default, blue tuned.</p>\n";
  for (std::size_t i = 0; i < r.compare_default.size(); ++i) {
    const ScenarioOutcome& d = r.compare_default[i];
    const ScenarioOutcome& t = r.compare_tuned[i];
    o << "<h3>" << text::html_escape(d.name) << " ("
      << (r.compare_is_validation[i] ? "validation" : "tuning") << ", <code>"
      << text::html_escape(d.scenario.string()) << "</code>)</h3>\n";
    for (const ScenarioOutcome* x : {&d, &t})
      if (x->failed)
        o << "<p class=\"worse\">" << (x == &d ? "default" : "tuned")
          << " failed: " << text::html_escape(x->message) << "</p>\n";
    o << "<table><tr><th>statistic</th><th>default</th><th>tuned</th><th>change</th></tr>\n";
    for (const Shown& s : shown_stats()) {
      const double a = outcome_stat(d, s.stat) * s.scale, b = outcome_stat(t, s.stat) * s.scale;
      o << "<tr><td>" << text::html_escape(s.label) << " (" << s.unit << ")</td><td class=\"n\">"
        << show(a) << "</td><td class=\"n\">" << show(b) << "</td><td class=\"n "
        << (b < a   ? "better"
            : b > a ? "worse"
                    : "")
        << "\">" << change(a, b) << "</td></tr>\n";
    }
    o << "</table>\n";
    bar_chart(o, d, t);
    o << "\n";
  }
  o << "</body></html>\n";
  return o.str();
}

}  // namespace arttrack::sim
