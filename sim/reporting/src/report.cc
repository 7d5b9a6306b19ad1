#include "arttrack/sim/report.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>

#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/tracker/error.h"
#include "report_sections.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace report {

using chart::fixed;

std::string method_colour(const std::string& method, std::size_t index) {
  if (method == "encoders_only") return "#E69F00";
  if (method == "camera_offset_only") return "#0072B2";
  if (method == "full_fusion") return "#009E73";
  if (method == "vision_only") return "#CC79A7";
  static const std::array<const char*, 4> other = {"#D55E00", "#56B4E9", "#F0E442", "#000000"};
  return other[index % other.size()];
}

const MethodRun* method_run(const RunResult& run, const std::string& method) {
  for (const MethodRun& m : run.methods)
    if (m.method == method) return &m;
  return nullptr;
}

std::size_t method_index(const ScenarioResult& r, const std::string& method) {
  return std::size_t(std::find(r.methods.begin(), r.methods.end(), method) - r.methods.begin());
}

std::string end_effector_list(const ScenarioResult& r) {
  std::string out;
  for (std::size_t i = 0; i < r.end_effectors.size(); ++i)
    out += (i ? ", " : "") + r.end_effectors[i];
  return out;
}

chart::LineChart time_chart(const ScenarioResult& r, const std::string& id, double width,
                            double height, const std::string& y_label) {
  chart::LineChart c;
  c.id = id;
  c.frame.width = width;
  c.frame.height = height;
  c.x_label = "time, s";
  c.y_label = y_label;
  c.x_hi = r.duration_s > 0 ? r.duration_s : 1.0;
  return c;
}

namespace {

void header(std::ostream& o, const ScenarioResult& r) {
  o << "<h1>arttrack run: " << text::html_escape(r.scenario) << "</h1>\n<dl class=\"meta\">";
  o << "<dt>scenario file</dt><dd>" << text::html_escape(r.source) << "</dd>";
  o << "<dt>duration</dt><dd>" << fixed(r.duration_s, 1) << " s simulated per run</dd>";
  o << "<dt>runs</dt><dd>" << r.runs.size() << "</dd><dt>seeds</dt><dd>";
  for (std::size_t i = 0; i < r.seeds.size(); ++i) o << (i ? ", " : "") << r.seeds[i];
  o << "</dd><dt>methods</dt><dd>";
  for (std::size_t i = 0; i < r.methods.size(); ++i)
    o << "<span class=\"key\" style=\"background:" << method_colour(r.methods[i], i) << "\"></span>"
      << text::html_escape(r.methods[i]);
  o << "</dd><dt>scored end effectors</dt><dd>";
  for (std::size_t i = 0; i < r.end_effectors.size(); ++i)
    o << (i ? ", " : "") << text::html_escape(r.end_effectors[i]);
  int captured = 0, delivered = 0;
  for (const RunResult& run : r.runs)
    captured += run.frames_captured, delivered += run.frames_delivered;
  o << "</dd><dt>depth frames</dt><dd>" << captured << " captured, " << delivered
    << " delivered to the trackers (all runs)</dd></dl>\n";
  if (r.duration_s <= r.scoring.converged_after_s)
    o << "<p class=\"warn\"><strong>Short run:</strong> it ends at " << fixed(r.duration_s, 1)
      << "&nbsp;s, before the converged window starts (scoring.converged_after_s = "
      << fixed(r.scoring.converged_after_s, 1)
      << "&nbsp;s), so the converged statistics, times to converge and lost runs below are "
         "empty. Run longer, or set scoring.converged_after_s lower.</p>\n";
  o << "<p class=\"read\">How to read: errors are of the end-effector pose in each method's "
       "<em>estimated</em> camera frame against the true pose in the true camera frame (paper "
       "Sec.&nbsp;V); lower is better. Boxes span the middle half of the samples (p25&ndash;p75), "
       "ticks mark p1, the median p50 (thick, value beside it) and p99; &ldquo;converged&rdquo; "
       "keeps the samples from "
    << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on. Axes marked &ldquo;log scale&rdquo; are logarithmic because the values "
       "span more than two decades. With several end effectors, charts show the worst of them "
       "at each sample (the tables have each one). &infin; or &ldquo;lost&rdquo; on a chart: a "
       "lost estimate (counted as "
       "the worst error). Dashed black lines are the simulator's truth.</p>\n";
}

}  // namespace
}  // namespace report

std::string report_html(const ScenarioResult& r) {
  std::ostringstream o;
  o << chart::page_start("arttrack: " + r.scenario);
  report::header(o, r);
  report::verdict_section(o, r);
  report::box_section(o, r);
  report::error_time_section(o, r);
  report::health_section(o, r);
  report::consistency_time_section(o, r);
  report::bias_section(o, r);
  report::camera_section(o, r);
  report::frames_section(o, r);
  report::table_section(o, r);
  o << chart::page_end();
  return o.str();
}

void write_report_html(const fs::path& file, const ScenarioResult& result) {
  const std::string html = report_html(result);
  std::ofstream out(file, std::ios::binary);
  out << html;
  out.close();
  if (!out) throw InputError(file.string() + ": cannot write the report");
}

}  // namespace arttrack::sim
