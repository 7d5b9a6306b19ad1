// sweep.html: the sweep's page (sweep.h), drawn with the chart layer.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/sweep.h"
#include "arttrack/tracker/internal/non_finite.h"

namespace arttrack::sim {

namespace {

using Cells = std::map<std::size_t, const CellResult*>;

// A value as a heat map cell shows it: three digits, "never" for +inf.
std::string short_value(double v) {
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return v > 0 ? "never" : "-inf";
  if (std::fabs(v) < 5e-4) return "0";
  if (std::fabs(v) >= 100) return text::format_g(std::round(v), 6);
  return text::format_g(v, 3);
}

// Whether a method fails in a cell: 1 fails, 0 holds, -1 unknown.
int fail_state(const SweepSpec& spec, const CellResult* c, std::size_t method) {
  if (!c || c->failed) return -1;
  const auto& stats = sweep_statistics();
  const std::size_t s =
      std::size_t(std::find(stats.begin(), stats.end(), spec.fail_statistic) - stats.begin());
  const double v = c->stats[method][s];
  if (std::isnan(v)) return -1;
  return v > spec.fail_threshold_m ? 1 : 0;
}

const CellResult* find_cell(const Cells& cells, std::size_t cell) {
  const auto it = cells.find(cell);
  return it == cells.end() ? nullptr : it->second;
}

std::string axis_values_text(const GridAxis& a) {
  std::string s;
  for (std::size_t i = 0; i < a.values.size(); ++i) s += (i ? ", " : "") + a.values[i];
  return s;
}

void intro(std::ostream& o, const SweepSpec& spec, const std::vector<CellResult>& cells,
           std::size_t n_failed) {
  o << "<h1>Sweep: " << text::html_escape(spec.scenario_name) << "</h1>\n<p>Scenario <code>"
    << text::html_escape(spec.scenario.string()) << "</code>";
  for (const std::string& ov : spec.overrides)
    o << " <code>--set " << text::html_escape(ov) << "</code>";
  o << "; " << spec.runs << " run(s) per cell, seeds from each cell's overrides and the scenario "
    << "seed " << spec.scenario_seed << ". " << cells.size() << " of " << spec.cell_count()
    << " cells in these results, " << n_failed << " failed to run.</p>\n<table><tr>"
    << "<th class=\"m\">axis</th><th class=\"m\">key</th><th class=\"m\">values</th></tr>";
  const char* axis_role[] = {"x (across)", "y (up)"};
  for (std::size_t a = 0; a < spec.axes.size(); ++a)
    o << "<tr><td class=\"m\">"
      << (a < 2 ? std::string(axis_role[a]) : "panel " + std::to_string(a - 1))
      << "</td><td class=\"m\"><code>" << text::html_escape(spec.axes[a].key)
      << "</code></td><td class=\"m\">" << text::html_escape(axis_values_text(spec.axes[a]))
      << "</td></tr>";
  const StatisticUnit fail_unit = statistic_unit(spec.fail_statistic);
  o << "</table>\n<p>A method <b>fails</b> in a cell where its <code>"
    << text::html_escape(spec.fail_statistic) << "</code> exceeds "
    << text::format_g(spec.fail_threshold_m * fail_unit.scale, 6) << " " << fail_unit.shown
    << " (<code>--fail-threshold-m " << text::format_g(spec.fail_threshold_m, 6) << "</code>, in "
    << fail_unit.si << ")"
    << ": outlined in magenta on every map of that method; a thick black line separates failing "
       "cells from holding neighbours.</p>\n";
}

// Where each method breaks along the first axis, per value of the others.
void breaks_table(std::ostream& o, const SweepSpec& spec, const Cells& by_cell) {
  const GridAxis& a0 = spec.axes[0];
  const std::size_t rows = spec.cell_count() / a0.values.size();
  o << "<h2>Where each method breaks</h2>\n<table><tr><th class=\"m\">";
  for (std::size_t a = 1; a < spec.axes.size(); ++a)
    o << (a > 1 ? ", " : "") << "<code>" << text::html_escape(spec.axes[a].key) << "</code>";
  if (spec.axes.size() == 1) o << "&nbsp;";
  o << "</th>";
  for (const std::string& m : spec.methods)
    o << "<th class=\"m\">" << text::html_escape(m) << "</th>";
  o << "</tr>\n";
  bool any_known = false;
  for (std::size_t r = 0; r < rows; ++r) {
    // Cells of this row: axis 0 varies slowest, so stride `rows`.
    const std::vector<std::size_t> coord = spec.cell_coordinates(r);
    o << "<tr><td class=\"m\">";
    for (std::size_t a = 1; a < spec.axes.size(); ++a)
      o << (a > 1 ? ", " : "") << text::html_escape(spec.axes[a].values[coord[a]]);
    if (spec.axes.size() == 1) o << "all";
    o << "</td>";
    for (std::size_t m = 0; m < spec.methods.size(); ++m) {
      std::vector<int> f;
      for (std::size_t x = 0; x < a0.values.size(); ++x)
        f.push_back(fail_state(spec, find_cell(by_cell, x * rows + r), m));
      std::vector<std::size_t> failing;
      std::size_t unknown = 0;
      for (std::size_t x = 0; x < f.size(); ++x) {
        if (f[x] == 1) failing.push_back(x);
        if (f[x] < 0) ++unknown;
      }
      any_known = any_known || unknown < f.size();
      std::string text;
      if (failing.empty()) {
        text = unknown == f.size() ? "unknown (no value)" : unknown ? "holds where known" : "holds";
      } else if (failing.size() == f.size()) {
        text = "fails everywhere";
      } else if (failing.back() == f.size() - 1 && failing.size() == f.size() - failing.front()) {
        text = "fails from " + a0.key + " = " + a0.values[failing.front()];
      } else {
        text = "fails at " + a0.key + " = ";
        for (std::size_t i = 0; i < failing.size(); ++i)
          text += (i ? ", " : "") + a0.values[failing[i]];
      }
      o << "<td class=\"m" << (failing.empty() ? "" : " fail") << "\">" << text::html_escape(text)
        << "</td>";
    }
    o << "</tr>\n";
  }
  o << "</table>\n";
  if (!any_known)
    o << "<p class=\"warn\">No cell has a value of <code>" << text::html_escape(spec.fail_statistic)
      << "</code>: nothing is known about where the methods fail. A converged_ statistic has "
         "no value when the runs end before <code>scoring.converged_after_s</code> (no "
         "converged window): run longer, or choose another --fail-statistic.</p>\n";
}

void failed_cells(std::ostream& o, const SweepSpec& spec, const std::vector<CellResult>& cells) {
  o << "<h2>Cells that failed to run</h2>\n<table><tr><th>cell</th><th class=\"m\">overrides</th>"
       "<th class=\"m\">message</th></tr>\n";
  for (const CellResult& c : cells) {
    if (!c.failed) continue;
    std::string ov;
    for (const std::string& s : spec.cell_overrides(c.cell)) ov += (ov.empty() ? "" : " ") + s;
    o << "<tr><td>" << c.cell << "</td><td class=\"m\"><code>" << text::html_escape(ov)
      << "</code></td><td class=\"m\">" << text::html_escape(c.message) << "</td></tr>\n";
  }
  o << "</table>\n";
}

// The colour scale of one statistic over all methods and cells, in the
// unit shown: logarithmic for errors spanning more than a decade, over at
// most three decades (a numerically zero error would squash the rest).
chart::ColourScale statistic_scale(const SweepSpec& spec, const std::vector<CellResult>& cells,
                                   std::size_t stat, bool& any) {
  const std::string& name = sweep_statistics()[stat];
  const double shown = statistic_unit(name).scale;
  double lo = kInf, hi = -kInf;
  for (const CellResult& c : cells)
    if (!c.failed)
      for (std::size_t m = 0; m < spec.methods.size(); ++m) {
        const double v = c.stats[m][stat];
        if (!std::isfinite(v)) continue;
        lo = std::min(lo, v * shown);
        hi = std::max(hi, v * shown);
      }
  chart::ColourScale scale;
  any = lo <= hi;
  if (!any) return scale;
  scale.lo = lo;
  scale.hi = hi;
  scale.log = name != "convergence_time_s" && hi > 0 && hi > 10 * lo;
  if (scale.log) scale.lo = std::max(lo, hi * 1e-3);
  return scale;
}

// The heat map of one method and statistic: axis 0 across, axis 1 up (if
// any), the other axes fixed at `rest` (value indices of axes 2...).
chart::HeatMap method_map(const SweepSpec& spec, const Cells& by_cell, std::size_t method,
                          std::size_t stat, const chart::ColourScale& scale,
                          const std::vector<std::size_t>& rest) {
  const StatisticUnit unit = statistic_unit(sweep_statistics()[stat]);
  chart::HeatMap map;
  map.scale = scale;
  map.x_values = spec.axes[0].values;
  map.x_label = spec.axes[0].key;
  if (spec.axes.size() > 1) {
    map.y_values = spec.axes[1].values;
    map.y_label = spec.axes[1].key;
  }
  const std::size_t ny = std::max<std::size_t>(1, map.y_values.size());
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < map.x_values.size(); ++x) {
      std::vector<std::size_t> coord{x};
      if (spec.axes.size() > 1) coord.push_back(y);
      coord.insert(coord.end(), rest.begin(), rest.end());
      std::size_t index = 0;
      for (std::size_t a = 0; a < spec.axes.size(); ++a)
        index = index * spec.axes[a].values.size() + coord[a];
      chart::HeatCell cell;
      cell.tooltip = "cell " + std::to_string(index);
      for (const std::string& ov : spec.cell_overrides(index)) cell.tooltip += "\n" + ov;
      const CellResult* c = find_cell(by_cell, index);
      if (!c) {
        cell.tooltip += "\nnot run in this part";
      } else if (c->failed) {
        cell.state = chart::HeatCell::State::kFailed;
        cell.tooltip += "\nFAILED: " + c->message;
      } else {
        cell.state = chart::HeatCell::State::kValue;
        cell.value = c->stats[method][stat] * unit.scale;
        cell.text = short_value(cell.value);
        cell.tooltip += "\n" + cell.text + " " + unit.shown;
        cell.group = fail_state(spec, c, method);
        cell.outlined = cell.group == 1;
      }
      map.cells.push_back(std::move(cell));
    }
  return map;
}

void heat_maps(std::ostream& o, const SweepSpec& spec, const std::vector<CellResult>& cells,
               const Cells& by_cell) {
  // Panels: every combination of the axes after the first two.
  std::size_t panels = 1;
  for (std::size_t a = 2; a < spec.axes.size(); ++a) panels *= spec.axes[a].values.size();
  o << "<h2>Heat maps</h2>\n<p>Across: <code>" << text::html_escape(spec.axes[0].key) << "</code>";
  if (spec.axes.size() > 1) o << "; up: <code>" << text::html_escape(spec.axes[1].key) << "</code>";
  if (panels > 1) o << "; one map per value of the other axes";
  o << ". Hover a cell for its overrides and value.</p>\n";
  chart::legend(o, "cell-key",
                {{"run failed", "#bbb", chart::Mark::kCross, chart::Stroke::kSolid},
                 {"never converged", "#111", chart::Mark::kSwatch, chart::Stroke::kSolid},
                 {"no value", "#eee", chart::Mark::kSwatch, chart::Stroke::kSolid},
                 {"not in these results", "#aaa", chart::Mark::kDashedBox, chart::Stroke::kSolid},
                 {"method fails", "#ff00ff", chart::Mark::kOutline, chart::Stroke::kSolid},
                 {"fails | holds", "#000", chart::Mark::kLine, chart::Stroke::kSolid}},
                760);
  const std::set<std::string> open = {"p50_translation_m", "converged_p50_translation_m",
                                      "converged_p99_translation_m", "convergence_time_s"};
  const auto& stats = sweep_statistics();
  for (std::size_t s = 0; s < stats.size(); ++s) {
    const StatisticUnit unit = statistic_unit(stats[s]);
    bool any = false;
    const chart::ColourScale scale = statistic_scale(spec, cells, s, any);
    o << "<details" << (open.count(stats[s]) ? " open" : "") << "><summary>" << stats[s]
      << " (shown in " << unit.shown << ")</summary>\n<div class=\"one\">";
    if (any)
      chart::colour_bar(o, "colours-" + stats[s], scale, stats[s] + ", " + unit.shown);
    else
      o << "<p>No cell has a finite value.</p>";
    o << "</div>\n<div class=\"maps\">";
    for (std::size_t m = 0; m < spec.methods.size(); ++m)
      for (std::size_t p = 0; p < panels; ++p) {
        std::vector<std::size_t> rest(spec.axes.size() > 2 ? spec.axes.size() - 2 : 0);
        std::size_t q = p;
        for (std::size_t a = spec.axes.size(); a-- > 2;) {
          rest[a - 2] = q % spec.axes[a].values.size();
          q /= spec.axes[a].values.size();
        }
        chart::HeatMap map = method_map(spec, by_cell, m, s, scale, rest);
        map.id = stats[s] + "-" + spec.methods[m] + "-" + std::to_string(p);
        map.title = spec.methods[m];
        for (std::size_t a = 2; a < spec.axes.size(); ++a)
          map.title +=
              (a > 2 ? ", " : " at ") + spec.axes[a].key + " = " + spec.axes[a].values[rest[a - 2]];
        o << "<div>";
        chart::heat_map(o, map);
        o << "</div>";
      }
    o << "</div>\n</details>\n";
  }
}

}  // namespace

std::string sweep_html(const SweepSpec& spec, const std::vector<CellResult>& cells) {
  Cells by_cell;
  for (const CellResult& c : cells) by_cell[c.cell] = &c;
  std::size_t n_failed = 0;
  for (const CellResult& c : cells) n_failed += c.failed;
  std::ostringstream o;
  o << chart::page_start("Sweep: " + spec.scenario_name);
  intro(o, spec, cells, n_failed);
  breaks_table(o, spec, by_cell);
  if (n_failed) failed_cells(o, spec, cells);
  heat_maps(o, spec, cells, by_cell);
  o << chart::page_end();
  return o.str();
}

}  // namespace arttrack::sim
