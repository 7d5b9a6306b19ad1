// tuning.html: the tuning page (tuning.h), drawn with the chart layer.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/sweep.h"
#include "arttrack/sim/tuning.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/units.h"

namespace arttrack::sim {

namespace {

// A statistic the page shows, in its display unit.
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
      {"converged_p50_rotation_rad", "converged rotation p50", kDegPerRad, "deg"},
      {"convergence_time_s", "convergence time", 1, "s"},
      {"p50_image_update_ms", "image update p50", 1, "ms"},
  };
  return s;
}

// A wall time: it varies from run to run, so a change is not a finding.
bool wall_time(const std::string& stat) { return stat.ends_with("_ms"); }

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

// The change from a to b, and its class: better or worse (lower is
// better), none for a wall time.
std::string change_cells(double a, double b, bool timing) {
  std::string pct;
  if (std::isfinite(a) && std::isfinite(b) && a != 0) {
    const double p = 100 * (b - a) / a;
    pct = text::format_g(p, 3) + "%";
    if (p > 0) pct.insert(pct.begin(), '+');
  }
  const char* cls = timing ? "" : b < a ? " better" : b > a ? " worse" : "";
  return "<td class=\"n" + std::string(cls) + "\">" + pct + (timing ? " (wall time)" : "") +
         "</td>";
}

// Grouped bars of the translation statistics, default against tuned.
void bars(std::ostream& o, const std::string& id, const ScenarioOutcome& d,
          const ScenarioOutcome& t) {
  chart::BarChart c;
  c.id = id;
  c.title = "Translation errors, default against tuned";
  c.y_label = "translation error, mm";
  chart::BarSeries def{"default", "#999999", {}}, tuned{"tuned", "#0072B2", {}};
  for (const Shown& s : shown_stats()) {
    if (s.unit != "mm") continue;
    c.categories.push_back(s.label);
    def.values.push_back(outcome_stat(d, s.stat) * s.scale);
    tuned.values.push_back(outcome_stat(t, s.stat) * s.scale);
  }
  c.series = {def, tuned};
  chart::bar_chart(o, c);
}

// The objective per evaluation (dots), the best so far (line) and the best
// evaluation (ring), in the statistic's display unit.
void search_chart(std::ostream& o, const TuningOptions& options, const TuningResult& r) {
  const StatisticUnit unit = statistic_unit(options.objective.statistic);
  chart::LineChart c;
  c.id = "search";
  c.title = "Objective per evaluation";
  c.frame.width = 760;
  c.frame.height = 300;
  c.x_label = "evaluation";
  c.y_label = "objective, " + unit.shown +
              (options.objective.time_penalty_per_ms > 0 ? " (with the time penalty)" : "");
  c.allow_log = true;
  c.integer_x = true;
  c.x_lo = 0.5;
  c.x_hi = double(r.history.size()) + 0.5;
  chart::Series evals, best_line, best, failed;
  evals.name = "evaluation";
  evals.colour = "#0072B2";
  evals.mark = chart::Mark::kDots;
  best_line.name = "best so far";
  best_line.colour = "#009E73";
  best.name = "best (evaluation " + std::to_string(r.history.at(r.best).index) + ")";
  best.colour = "#D55E00";
  best.mark = chart::Mark::kRing;
  failed.name = "failed or no value (counted as " + text::format_g(kFailedStatistic, 6) + " " +
                unit.si + ", off the scale)";
  failed.colour = "#999999";
  failed.mark = chart::Mark::kDots;
  double so_far = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < r.history.size(); ++i) {
    const double x = double(i + 1), v = r.history[i].objective;
    so_far = std::min(so_far, v);
    best_line.x.push_back(x);
    best_line.y.push_back(so_far * unit.scale);
    chart::Series& s = v >= kFailedStatistic ? failed : evals;
    s.x.push_back(x);
    s.y.push_back(v * unit.scale);
    if (v < kFailedStatistic) c.y_axis_values.push_back(v * unit.scale);
    if (i == r.best) {
      best.x.push_back(x);
      best.y.push_back(v * unit.scale);
    }
  }
  if (c.y_axis_values.empty()) c.y_axis_values = {0.0, 1.0};  // every evaluation failed
  c.series = {best_line, evals};
  if (!failed.x.empty()) c.series.push_back(failed);
  c.series.push_back(best);
  o << "<div class=\"one\">";
  chart::line_chart(o, c);
  o << "</div>\n";
}

void parameters_table(std::ostream& o, const TuningResult& r) {
  const Evaluation& best = r.history.at(r.best);
  o << "<h2>Parameters</h2>\n<table><tr><th class=\"m\">key</th><th class=\"m\">interval</th>"
       "<th>default</th><th>tuned</th></tr>\n";
  for (std::size_t i = 0; i < r.params.size(); ++i) {
    const TuningParameter& p = r.params[i];
    o << "<tr><td class=\"m\"><code>" << text::html_escape(p.key) << "</code></td><td class=\"m\">["
      << p.text(p.lo) << ", " << p.text(p.hi) << "]" << (p.integer ? " whole" : "") << "</td><td>"
      << (std::isnan(r.default_values[i]) ? "-" : text::format_g(r.default_values[i], 6))
      << "</td><td><b>" << p.text(best.values[i]) << "</b></td></tr>\n";
  }
  o << "</table>\n";
}

void scenario_section(std::ostream& o, const TuningResult& r, std::size_t i) {
  const ScenarioOutcome& d = r.compare_default[i];
  const ScenarioOutcome& t = r.compare_tuned[i];
  o << "<h3>" << text::html_escape(d.name) << " ("
    << (r.compare_is_validation[i] ? "validation" : "tuning") << ", <code>"
    << text::html_escape(d.scenario.string()) << "</code>)</h3>\n";
  for (const ScenarioOutcome* x : {&d, &t})
    if (x->failed)
      o << "<p class=\"worse\">" << (x == &d ? "default" : "tuned")
        << " failed: " << text::html_escape(x->message) << "</p>\n";
  o << "<div class=\"two\"><div><table><tr><th class=\"m\">statistic</th><th>default</th>"
       "<th>tuned</th><th>change</th></tr>\n";
  for (const Shown& s : shown_stats()) {
    const double a = outcome_stat(d, s.stat) * s.scale, b = outcome_stat(t, s.stat) * s.scale;
    o << "<tr><td class=\"m\">" << text::html_escape(s.label) << " (" << s.unit << ")</td><td>"
      << show(a) << "</td><td>" << show(b) << "</td>" << change_cells(a, b, wall_time(s.stat))
      << "</tr>\n";
  }
  o << "</table></div><div>";
  bars(o, "bars-" + std::to_string(i), d, t);
  o << "</div></div>\n";
}

}  // namespace

std::string tuning_html(const TuningOptions& options, const TuningResult& r) {
  std::ostringstream o;
  const Evaluation& best = r.history.at(r.best);
  const std::string what = options.objective.text() + " of " + options.objective.method;
  o << chart::page_start("Tuning: " + what) << "<h1>Tuning: " << text::html_escape(what)
    << "</h1>\n<p>";
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
    << ", objective " << text::format_g(best.objective, 6) << " ("
    << statistic_unit(options.objective.statistic).si << ").</p>\n";
  parameters_table(o, r);
  o << "<h2>Search</h2>\n";
  search_chart(o, options, r);
  o << "<h2>Default against tuned</h2>\n<table><tr><th class=\"m\">scenario</th><th "
       "class=\"m\">role</th><th>"
    << text::html_escape(options.objective.statistic)
    << " default</th><th>tuned</th><th>change</th></tr>\n";
  for (std::size_t i = 0; i < r.compare_default.size(); ++i) {
    const double a = r.compare_default[i].objective_statistic,
                 b = r.compare_tuned[i].objective_statistic;
    o << "<tr><td class=\"m\">" << text::html_escape(r.compare_default[i].name)
      << "</td><td class=\"m\">" << (r.compare_is_validation[i] ? "validation" : "tuning")
      << "</td><td>" << show(a) << "</td><td>" << show(b) << "</td>"
      << change_cells(a, b, wall_time(options.objective.statistic)) << "</tr>\n";
  }
  o << "</table>\n";
  for (std::size_t i = 0; i < r.compare_default.size(); ++i) scenario_section(o, r, i);
  o << chart::page_end();
  return o.str();
}

}  // namespace arttrack::sim
