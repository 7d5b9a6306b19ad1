// The run report's error charts: box plots per method, the translation error
// over time, the tracker's health over time, the consistency over time.
#include <algorithm>
#include <cmath>
#include <ostream>
#include <vector>

#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/report.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/units.h"
#include "report_sections.h"

namespace arttrack::sim::report {

using chart::fixed;

namespace {

// The worst over the scored end effectors of the translation error, m (NaN
// if any is: a lost estimate).
double worst_translation_m(const EstimateSample& s) {
  if (s.ee_error.empty()) return kNaN;
  double worst = 0;
  for (const PoseError& e : s.ee_error) {
    if (std::isnan(e.translation_m)) return kNaN;
    worst = std::max(worst, e.translation_m);
  }
  return worst;
}

double median_of(std::vector<double> v) {
  if (v.empty()) return kNaN;
  for (double& x : v)
    if (std::isnan(x)) x = kInf;  // lost counts as the worst
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// A box of percentiles p, in display units (times `scale`).
chart::Box box(const std::string& name, const std::string& colour, const Percentiles& p,
               double scale) {
  return {name,          colour,        p.p01 * scale, p.p25 * scale,
          p.p50 * scale, p.p75 * scale, p.p99 * scale, p.count};
}

}  // namespace

void box_section(std::ostream& o, const ScenarioResult& r) {
  o << "<h2>End-effector errors per method</h2>\n";
  if (r.end_effectors.size() > 1)
    o << "<p>Each sample counts the worst of " << text::html_escape(end_effector_list(r))
      << ".</p>\n";
  struct Quantity {
    const char* id;
    const char* name;
    const char* unit;
    double scale;
    Percentiles ErrorStats::*field;
  };
  const Quantity quantities[] = {{"translation", "Translation error", "translation error, mm", kMm,
                                  &ErrorStats::translation_m},
                                 {"rotation", "Angular error", "angular error, degrees", kDegPerRad,
                                  &ErrorStats::rotation_rad}};
  const std::string after = "from " + fixed(r.scoring.converged_after_s, 1) + " s on";
  for (const Quantity& q : quantities) {
    std::vector<chart::Box> all, conv;
    std::vector<double> values;
    for (std::size_t i = 0; i < r.method_results.size(); ++i) {
      const MethodResult& m = r.method_results[i];
      const std::string c = method_colour(m.method, i);
      all.push_back(box(m.method, c, m.summary.all.*q.field, q.scale));
      conv.push_back(box(m.method, c, m.summary.converged.*q.field, q.scale));
      for (const chart::Box* b : {&all.back(), &conv.back()})
        for (double v : {b->p01, b->p25, b->p50, b->p75, b->p99}) values.push_back(v);
    }
    // Both panels share the axis, so that they compare at a glance.
    const chart::Axis axis = chart::auto_axis(values, 7, true, 0, true);
    const std::size_t n_all = all.empty() ? 0 : all.front().count;
    const std::size_t n_conv = conv.empty() ? 0 : conv.front().count;
    o << "<div class=\"two\">\n";
    chart::box_plot(
        o, std::string("box-") + q.id + "-all",
        std::string(q.name) + ", all samples (n = " + std::to_string(n_all) + " per method)",
        q.unit, all, axis);
    chart::box_plot(o, std::string("box-") + q.id + "-converged",
                    std::string(q.name) + ", " + after + " (n = " + std::to_string(n_conv) + ")",
                    q.unit, conv, axis);
    o << "</div>\n";
  }
}

void error_time_section(std::ostream& o, const ScenarioResult& r) {
  if (r.runs.empty()) return;
  chart::LineChart c = time_chart(r, "error-time", 1160, 340, "translation error, mm");
  c.include_zero = true;
  c.allow_log = true;
  const std::string ees = end_effector_list(r);
  const bool median = r.runs.size() > 1;
  for (std::size_t mi = 0; mi < r.methods.size(); ++mi) {
    chart::Series s;
    s.name = r.methods[mi];
    s.colour = method_colour(s.name, mi);
    if (!median) {
      if (const MethodRun* m = method_run(r.runs[0], s.name))
        for (std::size_t i = 0; i < r.runs[0].truth.size() && i < m->samples.size(); ++i) {
          s.x.push_back(r.runs[0].truth[i].time_s);
          s.y.push_back(worst_translation_m(m->samples[i]) * kMm);
        }
    } else {
      // Runs are sampled at their own camera times: hold each run's last
      // sample on a common grid, then take the median across runs.
      const int n = 600;
      std::vector<std::size_t> cursor(r.runs.size(), 0);
      for (int g = 0; g <= n; ++g) {
        const double t = c.x_hi * g / n;
        std::vector<double> v;
        for (std::size_t k = 0; k < r.runs.size(); ++k) {
          const RunResult& run = r.runs[k];
          const MethodRun* m = method_run(run, s.name);
          if (!m) continue;
          std::size_t& i = cursor[k];
          while (i + 1 < run.truth.size() && i + 1 < m->samples.size() &&
                 run.truth[i + 1].time_s <= t)
            ++i;
          if (i < m->samples.size() && i < run.truth.size() && run.truth[i].time_s <= t)
            v.push_back(worst_translation_m(m->samples[i]) * kMm);
        }
        if (v.empty()) continue;
        s.x.push_back(t);
        s.y.push_back(median_of(v));
      }
    }
    c.series.push_back(std::move(s));
  }
  c.title = std::string("Translation error over time, ") +
            (median ? "median over " + std::to_string(r.runs.size()) + " runs" : "run 0") +
            (r.end_effectors.size() > 1 ? " (worst of " + ees + ")" : " (" + ees + ")");
  c.x_marks.emplace_back(r.scoring.converged_after_s, "converged window from here");
  c.y_marks.emplace_back(r.scoring.convergence_threshold_m * kMm, "convergence threshold");
  o << "<h2>Error over time</h2>\n";
  chart::line_chart(o, c);
}

// The tracker's own verdict over time (TrackerEstimate::health, run 0): the
// share of the estimate's rendered robot that the image contradicts (sees
// through) and explains, and when it called itself lost.
void health_section(std::ostream& o, const ScenarioResult& r) {
  if (r.runs.empty()) return;
  const RunResult& run = r.runs[0];
  chart::LineChart c =
      time_chart(r, "health-time", 1160, 320, "share of the estimate's robot pixels, %");
  c.include_zero = true;
  c.min_span = 100;
  std::vector<std::string> lost;
  for (std::size_t mi = 0; mi < r.methods.size(); ++mi) {
    const MethodRun* m = method_run(run, r.methods[mi]);
    if (!m) continue;
    chart::Series contradicted, explained, abandoned, weakest;
    contradicted.name = r.methods[mi] + ": contradicted";
    explained.name = r.methods[mi] + ": explained";
    abandoned.name = r.methods[mi] + ": abandoned";
    weakest.name = r.methods[mi] + ": weakest part explained";
    contradicted.colour = explained.colour = abandoned.colour = weakest.colour =
        method_colour(r.methods[mi], mi);
    explained.stroke = chart::Stroke::kDashed;
    abandoned.stroke = chart::Stroke::kDotted;
    weakest.mark = chart::Mark::kDots;
    double lost_s = 0, previous_t = 0;
    bool any = false;
    for (std::size_t i = 0; i < run.truth.size() && i < m->samples.size(); ++i) {
      const TrackingHealth& h = m->samples[i].health;
      const double t = run.truth[i].time_s;
      if (h.state == TrackingHealth::State::kLost) lost_s += t - previous_t;
      previous_t = t;
      if (h.state == TrackingHealth::State::kNoImage) continue;
      any = true;
      contradicted.x.push_back(t);
      contradicted.y.push_back(100 * h.whole.contradicted_fraction);
      explained.x.push_back(t);
      explained.y.push_back(100 * h.whole.explained_fraction);
      abandoned.x.push_back(t);
      abandoned.y.push_back(100 * h.whole.abandoned_fraction);
      weakest.x.push_back(t);
      weakest.y.push_back(100 * h.weakest_part_explained_fraction());
    }
    if (!any) continue;
    lost.push_back(text::html_escape(r.methods[mi]) + ": lost for " + fixed(lost_s, 1) + " s");
    c.series.push_back(std::move(contradicted));
    c.series.push_back(std::move(explained));
    c.series.push_back(std::move(abandoned));
    c.series.push_back(std::move(weakest));
  }
  if (c.series.empty()) return;
  c.title = "Health over time, run 0: the estimate's render against the image";
  o << "<h2>Tracker health</h2>\n<p>Solid: share of the estimate's rendered robot pixels that "
       "the camera sees through (contradicted); dashed: share within the explained depth; "
       "dotted: share of the pixels the estimate explained at its last good image that still "
       "show the same depth but are no longer explained (abandoned: an estimate that left a "
       "robot that did not move); dots: the share of its least explained part (the links after one "
       "joint) that the image explains (below health.unconfirmed_explained_fraction the chain is "
       "unconfirmed and searched again). "
    << "Lost (the tracker's own state): ";
  for (std::size_t i = 0; i < lost.size(); ++i) o << (i ? "; " : "") << lost[i];
  o << ".</p>\n";
  chart::line_chart(o, c);
}

// Whether a filter knows when it is wrong, over time: a share in the band
// over the whole run can be a too-sure start averaged with a too-cautious
// steady state (docs/accuracy.md, "Coverage over time").
void consistency_time_section(std::ostream& o, const ScenarioResult& r) {
  if (r.runs.empty()) return;
  chart::LineChart c = time_chart(r, "consistency-time", 1160, 320, "truth within 2 sigma, %");
  c.include_zero = true;
  c.min_span = 100;
  const double bin_s = std::max(0.25, r.duration_s / 40);
  // One legend entry per method (its colour) and per quantity (its stroke):
  // methods x quantities entries would not fit.
  c.legend = false;
  struct Part {
    const char* name;
    Coverage ConsistencyBin::*field;
    chart::Stroke stroke;
  };
  const Part parts[] = {
      {"angles", &ConsistencyBin::angles, chart::Stroke::kSolid},
      {"biases", &ConsistencyBin::biases, chart::Stroke::kDashed},
      {"camera offset", &ConsistencyBin::camera, chart::Stroke::kDotted},
      {"end-effector position", &ConsistencyBin::end_effector_position, chart::Stroke::kDashDot},
      {"end-effector rotation", &ConsistencyBin::end_effector_rotation,
       chart::Stroke::kDashDotDot}};
  std::vector<chart::LegendEntry> entries;
  for (std::size_t mi = 0; mi < r.methods.size(); ++mi) {
    const std::size_t series_before = c.series.size();
    const std::vector<ConsistencyBin> bins = consistency_over_time(r, r.methods[mi], bin_s);
    for (const Part& part : parts) {
      chart::Series s;
      s.name = r.methods[mi] + ": " + part.name;
      s.colour = method_colour(r.methods[mi], mi);
      s.stroke = part.stroke;
      for (const ConsistencyBin& b : bins) {
        const Coverage& cov = b.*part.field;
        if (cov.estimated == 0) continue;
        s.x.push_back(std::min(b.from_s + 0.5 * bin_s, r.duration_s));
        s.y.push_back(100 * cov.fraction());
      }
      if (!s.x.empty()) c.series.push_back(std::move(s));
    }
    if (c.series.size() > series_before)
      entries.push_back({r.methods[mi], method_colour(r.methods[mi], mi), chart::Mark::kSwatch});
  }
  if (c.series.empty()) return;
  c.title = "Truth within 2 sigma over time, every run pooled, per " + fixed(bin_s, 2) + " s";
  c.x_marks.emplace_back(r.scoring.converged_after_s, "converged window from here");
  c.y_marks.emplace_back(95, "95%");
  for (const Part& part : parts)
    entries.push_back({part.name, "#555", chart::Mark::kLine, part.stroke});
  o << "<h2>Consistency over time</h2>\n<p>The share of samples (every joint or virtual camera "
       "joint, and every end effector's pose: its three position and three rotation components "
       "in the camera's axes, pooled over the end effectors) whose true value lies within two "
       "of the standard deviations the method reports, per stretch of time. About 95% for an "
       "honest filter; below it the method claims more certainty than it has, at 100% less. "
       "The tables give the same shares over all samples and over the converged window.</p>\n";
  chart::legend(o, "consistency-legend", entries);
  chart::line_chart(o, c);
}

}  // namespace arttrack::sim::report

namespace arttrack::sim {

std::vector<ConsistencyBin> consistency_over_time(const ScenarioResult& r,
                                                  const std::string& method, double bin_s) {
  if (!(bin_s > 0)) return {};
  const std::size_t bins =
      std::size_t(std::max(1.0, std::ceil(r.duration_s / bin_s - 1e-9)));  // 20 / 0.5: 40
  std::vector<ConsistencyBin> out(bins);
  for (std::size_t b = 0; b < bins; ++b) out[b].from_s = double(b) * bin_s;
  for (const RunResult& run : r.runs) {
    const MethodRun* m = report::method_run(run, method);
    if (!m) continue;
    for (std::size_t i = 0; i < run.truth.size() && i < m->samples.size(); ++i) {
      const TruthSample& truth = run.truth[i];
      const EstimateSample& e = m->samples[i];
      ConsistencyBin& bin =
          out[std::min(bins - 1, std::size_t(std::max(0.0, truth.time_s / bin_s)))];
      // As the scorer takes them (method_trackers.cc): estimate - truth
      // against the reported standard deviation, 0 meaning not estimated.
      if (e.angle_std_rad.size() == truth.angle_rad.size() &&
          e.angle_rad.size() == truth.angle_rad.size())
        for (Eigen::Index j = 0; j < truth.angle_rad.size(); ++j)
          bin.angles.add(e.angle_rad[j] - truth.angle_rad[j], e.angle_std_rad[j]);
      if (e.bias_std_rad.size() == truth.bias_rad.size() &&
          e.bias_rad.size() == truth.bias_rad.size())
        for (Eigen::Index j = 0; j < truth.bias_rad.size(); ++j)
          bin.biases.add(e.bias_rad[j] - truth.bias_rad[j], e.bias_std_rad[j]);
      if (truth.T_base_camera)
        for (int k = 0; k < 6; ++k)
          bin.camera.add(e.camera_offset[k] - truth.camera_offset[k], e.camera_offset_std[k]);
      // The end-effector poses as score_estimate and stats_from count them:
      // each end effector's pose_error_vector against the square roots of
      // its covariance's diagonal (ee_std, empty without one), position
      // then rotation, pooled over the end effectors.
      if (e.ee_std.size() == e.ee_error_vector.size())
        for (std::size_t k = 0; k < e.ee_std.size(); ++k)
          for (int c = 0; c < 6; ++c)
            (c < 3 ? bin.end_effector_position : bin.end_effector_rotation)
                .add(e.ee_error_vector[k][c], e.ee_std[k][c]);
    }
  }
  return out;
}

}  // namespace arttrack::sim
