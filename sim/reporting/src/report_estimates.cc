// The run report's estimates against the simulator's truth: full_fusion's
// encoder bias per joint and each method's camera offset, over time (run 0).
#include <limits>
#include <ostream>

#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/tracker/units.h"
#include "report_sections.h"

namespace arttrack::sim::report {

namespace {

// The truth's style on every chart of these sections.
chart::Series truth_series(const std::string& name) {
  chart::Series s;
  s.name = name;
  s.colour = "#000";
  s.stroke = chart::Stroke::kDashed;
  return s;
}

// A small multiple over the run's time: no legend of its own (one legend
// over the grid), few ticks.
chart::LineChart small_time_chart(const ScenarioResult& r, const std::string& id,
                                  const std::string& title, double width, double height,
                                  const std::string& y_label) {
  chart::LineChart c = time_chart(r, id, width, height, y_label);
  c.title = title;
  c.frame.left = 56;
  c.frame.right = 8;
  c.frame.top = 26;
  c.frame.bottom = 36;
  c.legend = false;
  c.y_ticks = 5;
  c.x_ticks = 5;
  return c;
}

}  // namespace

void bias_section(std::ostream& o, const ScenarioResult& r) {
  o << "<h2>Encoder bias: full_fusion's estimate against the truth (run 0)</h2>\n";
  const MethodRun* m = r.runs.empty() ? nullptr : method_run(r.runs[0], "full_fusion");
  if (!m) {
    o << "<p>full_fusion was not run: no bias estimate to show.</p>\n";
    return;
  }
  const std::string colour = method_colour("full_fusion", method_index(r, "full_fusion"));
  chart::Series est_style;
  est_style.name = "estimate";
  est_style.colour = colour;
  chart::legend(o, "bias-legend",
                {chart::legend_entry(truth_series("true bias")),
                 chart::legend_entry(est_style),
                 {"estimate \xC2\xB1 one standard deviation", colour, chart::Mark::kBand,
                  chart::Stroke::kSolid}});
  const RunResult& run = r.runs[0];
  o << "<div class=\"multi\">\n";
  for (std::size_t j = 0; j < r.joint_names.size(); ++j) {
    // A prismatic joint's bias is in metres: drawn in mm.
    const bool prismatic = r.is_prismatic(j);
    const double scale = prismatic ? kMm : kDegPerRad;
    chart::LineChart c = small_time_chart(r, "bias-" + r.joint_names[j], r.joint_names[j], 290, 180,
                                          prismatic ? "bias, mm" : "bias, deg");
    c.frame.left = 50;
    c.min_span = 1.0;
    c.line_width = 1.2;  // the band (often narrow) stays visible
    chart::Series truth = truth_series("true bias"), est = est_style;
    for (std::size_t i = 0; i < run.truth.size() && i < m->samples.size(); ++i) {
      const TruthSample& t = run.truth[i];
      const EstimateSample& s = m->samples[i];
      if (Eigen::Index(j) >= t.bias_rad.size() || Eigen::Index(j) >= s.bias_rad.size()) continue;
      truth.x.push_back(t.time_s);
      truth.y.push_back(t.bias_rad[j] * scale);
      est.x.push_back(t.time_s);
      est.y.push_back(s.bias_rad[j] * scale);
      const double sd = Eigen::Index(j) < s.bias_std_rad.size() ? s.bias_std_rad[j] : 0.0;
      est.band_lo.push_back((s.bias_rad[j] - sd) * scale);
      est.band_hi.push_back((s.bias_rad[j] + sd) * scale);
    }
    c.series = {std::move(est), std::move(truth)};
    chart::line_chart(o, c);
  }
  o << "</div>\n";
}

void camera_section(std::ostream& o, const ScenarioResult& r) {
  o << "<h2>Camera offset estimates (run 0)</h2>\n";
  std::vector<std::pair<std::size_t, const MethodRun*>> methods;
  if (!r.runs.empty())
    for (std::size_t i = 0; i < r.methods.size(); ++i)
      if (r.methods[i] != "encoders_only")  // every other method estimates the virtual joints
        if (const MethodRun* m = method_run(r.runs[0], r.methods[i])) methods.push_back({i, m});
  if (methods.empty()) {
    o << "<p>No method that estimates the camera offset was run.</p>\n";
    return;
  }
  const RunResult& run = r.runs[0];
  bool known = false;  // the simulator knows the true camera (datasets may not)
  for (const TruthSample& t : run.truth) known = known || t.T_base_camera.has_value();
  o << "<p>The virtual camera joints (translation, then roll, pitch, yaw about the nominal "
       "camera frame's axes) as each method estimates them"
    << (known ? ", and the true offset: the one that puts the nominal model's camera, at the "
                "true joint angles, on the simulator's camera"
              : "; the true camera is not known here")
    << ".</p>\n";
  std::vector<chart::LegendEntry> entries;
  if (known) entries.push_back(chart::legend_entry(truth_series("true offset")));
  for (const auto& [i, m] : methods)
    entries.push_back(
        {m->method, method_colour(m->method, i), chart::Mark::kLine, chart::Stroke::kSolid});
  chart::legend(o, "camera-legend", entries);
  o << "<div class=\"three\">\n";
  for (int k = 0; k < 6; ++k) {
    const bool translation = k < 3;
    const double scale = translation ? kMm : kDegPerRad;
    chart::LineChart c = small_time_chart(r, "camera-" + std::string(kCameraOffsetAxes[k]),
                                          "camera " + std::string(kCameraOffsetAxes[k]), 385, 200,
                                          translation ? "offset, mm" : "offset, deg");
    c.min_span = translation ? 2.0 : 0.2;
    for (const auto& [i, m] : methods) {
      chart::Series s;
      s.name = m->method;
      s.colour = method_colour(m->method, i);
      for (std::size_t n = 0; n < run.truth.size() && n < m->samples.size(); ++n) {
        s.x.push_back(run.truth[n].time_s);
        s.y.push_back(m->samples[n].camera_offset[k] * scale);
      }
      c.series.push_back(std::move(s));
    }
    if (known) {
      chart::Series truth = truth_series("true offset");
      for (const TruthSample& t : run.truth) {
        truth.x.push_back(t.time_s);
        truth.y.push_back(t.T_base_camera ? t.camera_offset[k] * scale
                                          : std::numeric_limits<double>::quiet_NaN());
      }
      c.series.push_back(std::move(truth));
    }
    chart::line_chart(o, c);
  }
  o << "</div>\n";
}

}  // namespace arttrack::sim::report
