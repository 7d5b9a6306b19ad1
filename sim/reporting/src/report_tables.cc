// The run report's tables: the verdict per method at the top; at the end the
// numbers of summary.json, lost runs and consistency, timings.
#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/run_outputs.h"
#include "arttrack/tracker/units.h"
#include "report_sections.h"

namespace arttrack::sim::report {

using chart::fixed;
using chart::significant;

// The page's answer first: per method, whether it converged, how fast, how
// often it was lost, and how often it was worse than encoders only; then the
// best method among those never lost.
void verdict_section(std::ostream& o, const ScenarioResult& r) {
  if (r.method_results.empty()) return;
  o << "<h2>Verdict</h2>\n<table><tr><th class=\"m\">method</th><th>verdict</th>"
       "<th>converged p50 / p99, mm</th><th>median time to converge</th><th>lost runs</th>"
       "<th>worse than encoders only</th></tr>\n";
  const MethodResult* best = nullptr;
  for (const MethodResult& m : r.method_results) {
    const MethodSummary& s = m.summary;
    const Percentiles& c = s.converged.translation_m;
    const double convergence_s = median_convergence_s(s);  // as in the tables below
    const auto never = std::size_t(
        std::count(s.time_to_converge_s.begin(), s.time_to_converge_s.end(), std::nullopt));
    const std::size_t lost = s.lost_runs();
    std::string verdict;
    if (c.count == 0)
      verdict = "no converged window";
    else if (lost > 0)
      verdict = "<strong>lost</strong> in " + std::to_string(lost) + " of " +
                std::to_string(s.num_runs) + " runs";
    else if (never == s.time_to_converge_s.size())
      verdict = "never converged";
    else
      verdict = "tracks";
    if (c.count > 0 && lost == 0 && (!best || c.p50 < best->summary.converged.translation_m.p50))
      best = &m;
    o << "<tr><td class=\"m\">" << text::html_escape(m.method) << "</td><td>" << verdict
      << "</td><td>"
      << (c.count ? fixed(c.p50 * kMm, 1) + " / " + fixed(c.p99 * kMm, 1) : std::string("-"))
      << "</td><td>"
      << (std::isfinite(convergence_s) ? fixed(convergence_s, 1) + "&nbsp;s" +
                                             (never ? " (" + std::to_string(never) + " never)" : "")
                                       : std::string("never"))
      << "</td><td>" << lost << " of " << s.num_runs << "</td><td>"
      << (s.converged.reference.compared
              ? fixed(100.0 * s.converged.reference.share_worse(), 0) + "% of samples"
              : std::string("-"))
      << "</td></tr>\n";
  }
  o << "</table>\n<p>";
  if (best)
    o << "Best: <strong>" << text::html_escape(best->method)
      << "</strong> (the lowest converged median among the methods never lost).";
  else
    o << "No method was both converged and never lost.";
  o << " Converged: samples from " << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on, the worst end effector per sample.</p>\n";
}

namespace {

// Runs in which an end effector is lost.
std::size_t lost_count(const EndEffectorSummary& e) {
  return std::size_t(
      std::count_if(e.lost.begin(), e.lost.end(), [](const auto& l) { return l.has_value(); }));
}

// "12.3%", or "not estimated".
std::string coverage_cell(const Coverage& c) {
  return c.estimated ? fixed(100.0 * c.fraction(), 1) + "%" : std::string("not estimated");
}

// The camera offset's share per axis, for the methods with camera truth: a
// pooled share in the band can be one axis never covered and five always
// (docs/accuracy.md, "The camera's axes").
void camera_axes_table(std::ostream& o, const ScenarioResult& r) {
  const auto has_camera = [](const MethodResult& m) {
    return m.summary.all.camera_offset_coverage.estimated > 0;
  };
  if (std::none_of(r.method_results.begin(), r.method_results.end(), has_camera)) return;
  o << "<p>The camera offset within 2&sigma; per axis: all samples / from "
    << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on. The pooled share above can sit in the band while one axis is never "
       "covered.</p>\n<table><tr><th class=\"m\">method</th>";
  for (std::string_view axis : kCameraOffsetAxes) o << "<th>" << axis << "</th>";
  o << "</tr>\n";
  for (const MethodResult& m : r.method_results) {
    if (!has_camera(m)) continue;
    o << "<tr><td class=\"m\">" << text::html_escape(m.method) << "</td>";
    for (std::size_t k = 0; k < kCameraOffsetAxes.size(); ++k)
      o << "<td>" << coverage_cell(m.summary.all.camera_axis_coverage[k]) << " / "
        << coverage_cell(m.summary.converged.camera_axis_coverage[k]) << "</td>";
    o << "</tr>\n";
  }
  o << "</table>\n";
}

// TrackingHealth::links per method: which links fit the model least.
void links_table(std::ostream& o, const ScenarioResult& r) {
  std::vector<const MethodResult*> with_links;
  for (const MethodResult& m : r.method_results)
    if (!m.links.empty()) with_links.push_back(&m);
  if (with_links.empty()) return;
  o << "<p>How far each link seems from the model: the size of its surface shift that the depth "
       "residuals show along the directions the images pin (the joints and the camera offset "
       "cannot take them up), in each run's last estimate; the median over the runs that pinned "
       "it, and how many did. A length the joints take up does not show. Then its scale: how "
       "much larger its geometry seems than the model's, about the link's frame (the median over "
       "the runs that sized it). A link far above the rest is where to look in the URDF.</p>\n"
       "<table><tr><th class=\"m\">link</th>";
  for (const MethodResult* m : with_links) o << "<th>" << text::html_escape(m->method) << "</th>";
  o << "</tr>\n";
  for (std::size_t g = 0; g < with_links.front()->links.size(); ++g) {
    o << "<tr><td class=\"m\">" << text::html_escape(with_links.front()->links[g].link) << "</td>";
    for (const MethodResult* m : with_links) {
      o << "<td>";
      if (g < m->links.size() && m->links[g].runs_pinned > 0)
        o << fixed(m->links[g].median_shift_m * kMm, 1) << "&nbsp;mm (" << m->links[g].runs_pinned
          << "/" << m->summary.num_runs << ")";
      else
        o << "not pinned";
      if (g < m->links.size() && m->links[g].runs_scaled > 0)
        o << ", scale " << (m->links[g].median_scale >= 0 ? "+" : "")
          << fixed(100 * m->links[g].median_scale, 1) << "%";
      o << "</td>";
    }
    o << "</tr>\n";
  }
  o << "</table>\n";
}

// TrackingHealth::encoder_noise_measured_rad per method: each encoder's
// white noise as its readings showed it, to set against the configuration.
void encoder_noise_table(std::ostream& o, const ScenarioResult& r) {
  std::vector<const MethodResult*> with_noise;
  for (const MethodResult& m : r.method_results)
    if (!m.encoder_noise_rad.empty()) with_noise.push_back(&m);
  if (with_noise.empty()) return;
  o << "<p>Each encoder's white noise as its readings show it (four consecutive readings about "
       "their parabola), in each run's last estimate, the median over the runs; degrees, mm for "
       "a prismatic joint. Compare it with the tracker's <code>encoder_noise_deg</code> "
       "(<code>encoder_noise_m</code>): over 1.25 times that, the tracker weighs the readings by "
       "it (<code>encoder_noise.from_readings</code>).</p>\n<table><tr><th "
       "class=\"m\">joint</th><th>unit</th>";
  for (const MethodResult* m : with_noise) o << "<th>" << text::html_escape(m->method) << "</th>";
  o << "</tr>\n";
  for (std::size_t j = 0; j < r.joint_names.size(); ++j) {
    const bool prismatic = r.is_prismatic(j);
    o << "<tr><td class=\"m\">" << text::html_escape(r.joint_names[j]) << "</td><td>"
      << (prismatic ? "mm" : "deg") << "</td>";
    for (const MethodResult* m : with_noise) {
      o << "<td>";
      if (j < m->encoder_noise_rad.size() && std::isfinite(m->encoder_noise_rad[j]))
        o << (prismatic ? fixed(m->encoder_noise_rad[j] * kMm, 3)
                        : fixed(m->encoder_noise_rad[j] * kDegPerRad, 4));
      else
        o << "no encoder";
      o << "</td>";
    }
    o << "</tr>\n";
  }
  o << "</table>\n";
}

void lost_and_consistency_section(std::ostream& o, const ScenarioResult& r) {
  o << "<h2>Lost runs, consistency and the camera</h2>\n<p>A run is <em>lost</em> for a method "
       "when an end effector's translation error stays above "
    << fixed(r.scoring.lost_threshold_m * kMm, 1) << "&nbsp;mm for more than "
    << significant(r.scoring.lost_after_s) << "&nbsp;s from "
    << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on. <em>Within 2&sigma;</em>: the share of samples (every joint or virtual camera "
       "joint; each position and rotation component of every scored end effector's pose, against "
       "the standard deviations of its reported covariance) whose true value lies within two of "
       "the standard deviations the method reports; "
       "about 95% for an honest filter, far less for an overconfident one, 100% for one too "
       "cautious. Over all samples, and from the converged window on: a filter can be too sure "
       "while it converges and too cautious after. The "
       "true camera offset is the one that puts the nominal model's camera, at the true joint "
       "angles, on the simulator's camera. <em>Camera frame</em>: the estimated camera frame "
       "(the nominal model at the estimated angles and camera offset) against the true one, "
       "relative to the robot base.</p>\n";
  o << "<table><tr><th class=\"m\" rowspan=\"2\">method</th><th rowspan=\"2\">lost runs</th>"
       "<th colspan=\"5\">within 2&sigma;, all samples</th><th colspan=\"5\">within 2&sigma;, "
       "from "
    << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on</th><th colspan=\"2\">camera frame, mm</th><th colspan=\"2\">camera frame, "
       "deg</th></tr><tr><th>angles</th><th>biases</th><th>camera offset</th><th>end-effector "
       "position</th><th>end-effector rotation</th><th>angles</th><th>biases</th><th>camera "
       "offset</th><th>end-effector position</th><th>end-effector rotation</th><th>p50</th>"
       "<th>p99</th><th>p50</th><th>p99</th></tr>\n";
  for (const MethodResult& m : r.method_results) {
    const ErrorStats& s = m.summary.all;
    const ErrorStats& c = m.summary.converged;
    o << "<tr><td class=\"m\">" << text::html_escape(m.method) << "</td><td>"
      << m.summary.lost_runs() << " of " << m.summary.num_runs << "</td><td>"
      << coverage_cell(s.angle_coverage) << "</td><td>" << coverage_cell(s.bias_coverage)
      << "</td><td>" << coverage_cell(s.camera_offset_coverage) << "</td><td>"
      << coverage_cell(s.end_effector_position_coverage) << "</td><td>"
      << coverage_cell(s.end_effector_rotation_coverage) << "</td><td>"
      << coverage_cell(c.angle_coverage) << "</td><td>" << coverage_cell(c.bias_coverage)
      << "</td><td>" << coverage_cell(c.camera_offset_coverage) << "</td><td>"
      << coverage_cell(c.end_effector_position_coverage) << "</td><td>"
      << coverage_cell(c.end_effector_rotation_coverage) << "</td><td>"
      << fixed(s.camera_translation_m.p50 * kMm, 2) << "</td><td>"
      << fixed(s.camera_translation_m.p99 * kMm, 2) << "</td><td>"
      << fixed(s.camera_rotation_rad.p50 * kDegPerRad, 3) << "</td><td>"
      << fixed(s.camera_rotation_rad.p99 * kDegPerRad, 3) << "</td></tr>\n";
  }
  o << "</table>\n";
  camera_axes_table(o, r);
  links_table(o, r);
  encoder_noise_table(o, r);
  std::ostringstream list;
  for (const MethodResult& m : r.method_results)
    for (std::size_t run = 0; run < m.summary.num_runs; ++run)
      for (const EndEffectorSummary& e : m.summary.end_effectors)
        if (run < e.lost.size() && e.lost[run]) {
          const std::string notes = lost_span_notes(*e.lost[run]);
          list << "<li>" << text::html_escape(m.method) << ": run " << run
               << (run < r.seeds.size() ? " (seed " + std::to_string(r.seeds[run]) + ")" : "")
               << ", " << text::html_escape(e.name) << ", from " << fixed(e.lost[run]->from_s, 2)
               << "&nbsp;s for " << fixed(e.lost[run]->duration_s, 2) << "&nbsp;s"
               << (notes.empty() ? "" : ", " + text::html_escape(notes)) << "</li>\n";
        }
  if (!list.str().empty()) o << "<p>Lost:</p><ul class=\"lost\">\n" << list.str() << "</ul>\n";
}

}  // namespace

void table_section(std::ostream& o, const ScenarioResult& r) {
  const bool several = r.end_effectors.size() > 1;
  o << "<h2>Summary</h2>\n<p>The numbers of summary.json, in millimetres and degrees "
       "(percentiles pooled over runs)"
    << (several ? "; per end effector, and the worst of them (per sample, the larger error)" : "")
    << ".</p>\n";
  std::ostringstream after;
  after << "from " << fixed(r.scoring.converged_after_s, 1) << " s on";
  const char* pct[5] = {"p1", "p25", "p50", "p75", "p99"};
  for (int part = 0; part < 2; ++part) {
    o << "<table><tr><th class=\"m\" rowspan=\"2\">method</th>";
    if (several) o << "<th class=\"m\" rowspan=\"2\">end effector</th>";
    o << "<th colspan=\"5\">translation, mm, " << (part ? after.str() : "all samples")
      << "</th><th colspan=\"5\">rotation, deg, " << (part ? after.str() : "all samples")
      << "</th><th rowspan=\"2\">samples</th>";
    if (part)
      o << "<th rowspan=\"2\">converged after, s<br>(median of runs; below "
        << fixed(r.scoring.convergence_threshold_m * kMm, 1)
        << " mm)</th><th rowspan=\"2\">worse than<br>encoders_only</th><th "
           "rowspan=\"2\">lost runs</th>";
    o << "</tr><tr>";
    for (int k = 0; k < 2; ++k)
      for (const char* p : pct) o << "<th>" << p << "</th>";
    o << "</tr>\n";
    auto row = [&](const std::string& method, const std::string* ee, const ErrorStats& s,
                   double conv, std::size_t lost, std::size_t runs) {
      o << "<tr><td class=\"m\">" << text::html_escape(method) << "</td>";
      if (ee) o << "<td class=\"m\">" << text::html_escape(*ee) << "</td>";
      const Percentiles& t = s.translation_m;
      for (double v : {t.p01, t.p25, t.p50, t.p75, t.p99})
        o << "<td>" << fixed(v * kMm, 2) << "</td>";
      const Percentiles& a = s.rotation_rad;
      for (double v : {a.p01, a.p25, a.p50, a.p75, a.p99})
        o << "<td>" << fixed(v * kDegPerRad, 3) << "</td>";
      o << "<td>" << t.count << "</td>";
      if (part)
        o << "<td>" << (std::isfinite(conv) ? fixed(conv, 1) : std::string("never")) << "</td><td>"
          << (s.reference.compared ? fixed(100.0 * s.reference.share_worse(), 0) + "%"
                                   : std::string("&ndash;"))
          << "</td><td>" << lost << " of " << runs << "</td>";
      o << "</tr>\n";
    };
    static const std::string kWorst = "worst";
    for (const MethodResult& m : r.method_results) {
      const MethodSummary& sm = m.summary;
      if (several)
        for (const EndEffectorSummary& e : sm.end_effectors)
          row(m.method, &e.name, part ? e.converged : e.all,
              median_convergence_s(e.time_to_converge_s), lost_count(e), sm.num_runs);
      row(m.method, several ? &kWorst : nullptr, part ? sm.converged : sm.all,
          median_convergence_s(sm), sm.lost_runs(), sm.num_runs);
    }
    o << "</table>\n";
  }
  lost_and_consistency_section(o, r);
  o << "<h2>Timing</h2>\n<p>Wall time of each tracker call on this machine (summary.json reports "
       "full_fusion's, else the first method's). Speed figures belong to the benchmarks; these "
       "only show where the time went in this run.</p>\n"
       "<table><tr><th class=\"m\" rowspan=\"2\">method</th><th colspan=\"2\">joint update, "
       "&micro;s</th><th colspan=\"2\">image update, ms</th><th rowspan=\"2\">evaluations<br>per "
       "image</th><th rowspan=\"2\">images<br>received</th><th rowspan=\"2\">applied</th><th "
       "rowspan=\"2\">dropped</th></tr><tr><th>p50</th><th>p99</th><th>p50</th><th>p99</th></tr>\n";
  for (const MethodResult& m : r.method_results) {
    long received = 0, applied = 0, dropped = 0;
    for (const RunResult& run : r.runs)
      if (const MethodRun* mr = method_run(run, m.method)) {
        received += mr->stats.images_received;
        applied += mr->stats.images_applied;
        dropped += mr->stats.images_dropped_too_old + mr->stats.images_dropped_backlog +
                   mr->stats.images_dropped_busy;
      }
    const MethodTiming& t = m.timing;
    o << "<tr><td class=\"m\">" << text::html_escape(m.method) << "</td><td>"
      << fixed(t.joint_update_us.p50, 2) << "</td><td>" << fixed(t.joint_update_us.p99, 2)
      << "</td><td>" << fixed(t.image_update_ms.p50, 2) << "</td><td>"
      << fixed(t.image_update_ms.p99, 2) << "</td><td>" << fixed(t.evaluations_per_image, 0)
      << "</td><td>" << received << "</td><td>" << applied << "</td><td>" << dropped
      << "</td></tr>\n";
  }
  o << "</table>\n";
  // The JSON itself, folded (no script needed): its text has no & < >.
  std::string json = summary_json(r);
  std::string escaped;
  for (char c : json)
    escaped += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : std::string(1, c);
  o << "<details><summary>summary.json</summary><pre>" << escaped << "</pre></details>\n";
}

}  // namespace arttrack::sim::report
