#include "arttrack/sim/run_outputs.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <sstream>
#include <type_traits>

#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/report.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

Json number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json five(const Percentiles& p) {
  return Json{{"p1", number(p.p01)},
              {"p25", number(p.p25)},
              {"p50", number(p.p50)},
              {"p75", number(p.p75)},
              {"p99", number(p.p99)}};
}

// The method whose timings are reported: full fusion, else the first.
const MethodResult* timing_method(const ScenarioResult& r) {
  if (const MethodResult* m = r.method("full_fusion")) return m;
  return r.method_results.empty() ? nullptr : &r.method_results.front();
}

// The end-effector statistics of a method's worst and of each end effector.
Json pose_json(const ErrorStats& all, const ErrorStats& converged,
               const std::vector<std::optional<double>>& time_to_converge_s) {
  return Json{{"translation_m", five(all.translation_m)},
              {"rotation_rad", five(all.rotation_rad)},
              {"converged_translation_m", five(converged.translation_m)},
              {"converged_rotation_rad", five(converged.rotation_rad)},
              {"convergence_time_s", number(median_convergence_s(time_to_converge_s))}};
}

// Share within two standard deviations; null when not estimated.
Json coverage(const Coverage& c) { return number(c.fraction()); }

Json consistency_json(const ErrorStats& s) {
  Json axes = Json::object();
  for (std::size_t k = 0; k < kCameraOffsetAxes.size(); ++k)
    axes[std::string(kCameraOffsetAxes[k])] = coverage(s.camera_axis_coverage[k]);
  return Json{{"angles", coverage(s.angle_coverage)},
              {"biases", coverage(s.bias_coverage)},
              {"camera_offset", coverage(s.camera_offset_coverage)},
              {"camera_offset_axes", axes},
              {"end_effector_position", coverage(s.end_effector_position_coverage)},
              {"end_effector_rotation", coverage(s.end_effector_rotation_coverage)}};
}

Json camera_json(const MethodSummary& m) {
  if (m.all.camera_translation_m.count == 0) return nullptr;
  return Json{{"translation_m", five(m.all.camera_translation_m)},
              {"rotation_rad", five(m.all.camera_rotation_rad)},
              {"converged_translation_m", five(m.converged.camera_translation_m)},
              {"converged_rotation_rad", five(m.converged.camera_rotation_rad)}};
}

Json lost_json(const ScenarioResult& r, const MethodSummary& m) {
  Json list = Json::array();
  for (std::size_t run = 0; run < m.num_runs; ++run)
    for (const EndEffectorSummary& e : m.end_effectors)
      if (run < e.lost.size() && e.lost[run])
        list.push_back(Json{{"run", run},
                            {"seed", run < r.seeds.size() ? Json(r.seeds[run]) : Json(nullptr)},
                            {"end_effector", e.name},
                            {"from_s", number(e.lost[run]->from_s)},
                            {"duration_s", number(e.lost[run]->duration_s)},
                            {"out_of_view_share", number(e.lost[run]->out_of_view_share)},
                            {"stretches", e.lost[run]->stretches},
                            {"total_s", number(e.lost[run]->total_s)}});
  return Json{{"runs", m.lost_runs()}, {"of", m.num_runs}, {"list", list}};
}

// Element j of per-joint statistics, or an empty one.
template <class T>
T joint_entry(const std::vector<T>& v, std::size_t j) {
  return j < v.size() ? v[j] : T{};
}

Json joints_json(const MethodSummary& m) {
  Json joints = Json::object();
  const ErrorStats &a = m.all, &c = m.converged;
  for (std::size_t j = 0; j < m.joint_names.size(); ++j)
    joints[m.joint_names[j]] = Json{
        {"angle_abs_error_rad", five(joint_entry(a.joint_angle_abs_error_rad, j))},
        {"bias_abs_error_rad", five(joint_entry(a.joint_bias_abs_error_rad, j))},
        {"converged_angle_abs_error_rad", five(joint_entry(c.joint_angle_abs_error_rad, j))},
        {"converged_bias_abs_error_rad", five(joint_entry(c.joint_bias_abs_error_rad, j))},
        {"angle_within_2sigma", coverage(joint_entry(a.joint_angle_coverage, j))},
        {"bias_within_2sigma", coverage(joint_entry(a.joint_bias_coverage, j))},
    };
  return joints;
}

// The inputs a method's trackers dropped, over all runs.
TrackerStats dropped_inputs(const ScenarioResult& r, std::size_t method) {
  TrackerStats sum;
  for (const RunResult& run : r.runs)
    if (method < run.methods.size()) {
      sum.joint_measurements_dropped += run.methods[method].stats.joint_measurements_dropped;
      sum.images_dropped_bad_stamp += run.methods[method].stats.images_dropped_bad_stamp;
    }
  return sum;
}

// Per link: the pinned surface shift and the scale, the medians of the
// runs' last estimates (null where no image pinned or sized it), and in
// how many runs.
Json links_json(const std::vector<LinkModelFit>& links) {
  Json j = Json::object();
  for (const LinkModelFit& l : links)
    j[l.link] = Json{{"pinned_shift_m", number(l.median_shift_m)},
                     {"runs_pinned", l.runs_pinned},
                     {"scale", number(l.median_scale)},
                     {"runs_scaled", l.runs_scaled}};
  return j;
}

Json counts_json(const HealthCounts& c) {
  return Json{{"runs", c.runs},
              {"acquisitions", c.acquisitions},
              {"chains_reacquired", c.chains_reacquired},
              {"refinements_accepted", c.refinements_accepted},
              {"unseen_priors_kept", c.unseen_priors_kept},
              {"images_with_unseen_motion", c.images_with_unseen_motion},
              {"hand_searches", c.hand_searches},
              {"hand_shifts_accepted", c.hand_shifts_accepted}};
}

Json recipe_json(const RunRecipe& p) {
  if (p.scenario_yaml.empty()) return nullptr;
  return Json{{"version", p.version},
              {"scenario_file", p.scenario_file},
              {"scenario_dir", p.scenario_dir},
              {"overrides", p.overrides},
              {"seed", p.seed},
              {"runs", p.runs},
              {"methods", p.methods},
              {"realtime", p.realtime},
              {"scenario", p.scenario_yaml},
              {"tracker", p.tracker_yaml}};
}

}  // namespace

std::string summary_json(const ScenarioResult& r) {
  Json j;
  j["scenario"] = r.scenario;
  j["runs"] = r.runs.size();
  j["seeds"] = r.seeds;
  // The robot each run simulated, where the scenario draws one per run.
  Json robots = Json::array();
  for (const RunResult& run : r.runs)
    if (!run.drawn_link_lengths_m.empty() || !run.drawn_shape_scales.empty())
      robots.push_back(Json{{"run", run.run},
                            {"seed", run.seed},
                            {"link_lengths_m", run.drawn_link_lengths_m},
                            {"shape_scale", run.drawn_shape_scales}});
  if (!robots.empty()) j["robots"] = robots;
  j["duration_s"] = r.duration_s;
  j["end_effectors"] = r.end_effectors;
  // The joints whose per-joint figures named _rad are metres.
  Json prismatic = Json::array();
  for (std::size_t k = 0; k < r.joint_names.size(); ++k)
    if (r.is_prismatic(k)) prismatic.push_back(r.joint_names[k]);
  j["prismatic_joints"] = prismatic;
  j["scoring"] = Json{{"converged_after_s", number(r.scoring.converged_after_s)},
                      {"convergence_threshold_m", number(r.scoring.convergence_threshold_m)},
                      {"lost_threshold_m", number(r.scoring.lost_threshold_m)},
                      {"lost_after_s", number(r.scoring.lost_after_s)}};
  Json methods = Json::object();
  for (const MethodResult& m : r.method_results) {
    const MethodSummary& s = m.summary;
    Json method = pose_json(s.all, s.converged, s.time_to_converge_s);
    Json ees = Json::object();
    for (const EndEffectorSummary& e : s.end_effectors) {
      ees[e.name] = pose_json(e.all, e.converged, e.time_to_converge_s);
      ees[e.name]["lost_runs"] =
          std::count_if(e.lost.begin(), e.lost.end(), [](const auto& l) { return l.has_value(); });
    }
    method["end_effectors"] = ees;
    method["lost"] = lost_json(r, s);
    method["camera"] = camera_json(s);
    method["consistency"] = consistency_json(s.all);
    method["converged_consistency"] = consistency_json(s.converged);
    method["joints"] = joints_json(s);
    if (!m.links.empty()) method["links_model_error"] = links_json(m.links);
    if (!m.encoder_noise_rad.empty()) {
      Json noise = Json::object();  // null: no encoder
      for (std::size_t j = 0; j < m.encoder_noise_rad.size() && j < r.joint_names.size(); ++j)
        noise[r.joint_names[j]] = number(m.encoder_noise_rad[j]);
      method["encoder_noise_measured_rad"] = noise;
    }
    method["health_counts"] = counts_json(m.counts);
    methods[m.method] = method;
  }
  j["methods"] = methods;
  const MethodResult* t = timing_method(r);
  const MethodTiming timing = t ? t->timing : MethodTiming{};
  j["timing"] = Json{
      {"joint_update_us",
       {{"p50", number(timing.joint_update_us.p50)}, {"p99", number(timing.joint_update_us.p99)}}},
      {"image_update_ms",
       {{"p50", number(timing.image_update_ms.p50)}, {"p99", number(timing.image_update_ms.p99)}}},
      {"evaluations_per_image", number(timing.evaluations_per_image)},
  };
  Json dropped = Json::object();
  for (std::size_t i = 0; i < r.method_results.size(); ++i) {
    const TrackerStats d = dropped_inputs(r, i);
    dropped[r.method_results[i].method] = Json{{"joint_measurements", d.joint_measurements_dropped},
                                               {"images_bad_stamp", d.images_dropped_bad_stamp}};
  }
  j["dropped"] = dropped;
  j["reproduce"] = recipe_json(r.recipe);
  return j.dump(2) + "\n";
}

TimeseriesTable timeseries_table(const ScenarioResult& r) {
  TimeseriesTable t;
  const auto add = [&](const std::string& name) { t.columns.push_back({name, {}, {}}); };
  add("time_s"), add("run");
  t.columns.push_back({"method", {}, {}, true});
  add("camera_frame"), add("occluded_fraction");
  for (const std::string& e : r.end_effectors) add("translation_m_" + e), add("rotation_rad_" + e);
  for (const std::string& j : r.joint_names)
    for (const char* suffix :
         {"_true_rad", "_est_rad", "_std_rad", "_true_bias_rad", "_est_bias_rad", "_bias_std_rad"})
      add(j + suffix);
  for (const char* name : {"cam_x_m",
                           "cam_y_m",
                           "cam_z_m",
                           "cam_roll_rad",
                           "cam_pitch_rad",
                           "cam_yaw_rad",
                           "cam_x_std_m",
                           "cam_y_std_m",
                           "cam_z_std_m",
                           "cam_roll_std_rad",
                           "cam_pitch_std_rad",
                           "cam_yaw_std_rad",
                           "camera_translation_m",
                           "camera_rotation_rad",
                           "cam_true_x_m",
                           "cam_true_y_m",
                           "cam_true_z_m",
                           "cam_true_roll_rad",
                           "cam_true_pitch_rad",
                           "cam_true_yaw_rad"})
    add(name);
  t.columns.push_back({"health_state", {}, {}, true});
  for (const char* name : {"health_explained_fraction", "health_contradicted_fraction",
                           "health_abandoned_fraction", "health_weakest_part_explained_fraction",
                           "health_unconfirmed_chains", "health_model_error_std_m"})
    add(name);
  static constexpr const char* kPoseComponents[6] = {"x_m",    "y_m",    "z_m",
                                                     "rx_rad", "ry_rad", "rz_rad"};
  for (const std::string& e : r.end_effectors)
    for (const char* part : {"_err_", "_std_", "_correction_"})
      for (const char* component : kPoseComponents) add(e + part + component);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const RunResult& run : r.runs) {
    for (std::size_t i = 0; i < run.truth.size(); ++i) {
      const TruthSample& truth = run.truth[i];
      for (const MethodRun& m : run.methods) {
        const EstimateSample& s = m.samples[i];
        auto column = t.columns.begin();
        const auto put = [&](double v) { (column++)->numbers.push_back(v); };
        put(truth.time_s), put(run.run);
        (column++)->text.push_back(m.method);
        put(truth.camera_frame ? 1 : 0), put(truth.occluded_fraction);
        for (const PoseError& e : s.ee_error) put(e.translation_m), put(e.rotation_rad);
        for (Eigen::Index j = 0; j < truth.angle_rad.size(); ++j)
          put(truth.angle_rad[j]), put(s.angle_rad[j]), put(s.angle_std_rad[j]),
              put(truth.bias_rad[j]), put(s.bias_rad[j]), put(s.bias_std_rad[j]);
        for (int k = 0; k < 6; ++k) put(s.camera_offset[k]);
        for (int k = 0; k < 6; ++k) put(s.camera_offset_std[k]);
        put(s.camera_error.translation_m), put(s.camera_error.rotation_rad);
        for (int k = 0; k < 6; ++k) put(truth.T_base_camera ? truth.camera_offset[k] : nan);
        (column++)->text.push_back(health_state_name(s.health.state));
        put(s.health.whole.explained_fraction), put(s.health.whole.contradicted_fraction),
            put(s.health.whole.abandoned_fraction), put(s.health.weakest_part_explained_fraction()),
            put(s.health.unconfirmed_chains()), put(s.health.model_error_std_m);
        for (std::size_t e = 0; e < r.end_effectors.size(); ++e) {
          const auto put6 = [&](const auto& v, std::size_t i) {
            for (int k = 0; k < 6; ++k) put(i < v.size() ? v[i][k] : nan);
          };
          put6(s.ee_error_vector, e), put6(s.ee_std, e), put6(s.ee_correction, e);
        }
      }
    }
  }
  t.rows = t.columns.front().numbers.size();
  return t;
}

void write_timeseries_csv(std::ostream& out, const ScenarioResult& r) {
  const TimeseriesTable t = timeseries_table(r);
  for (std::size_t c = 0; c < t.columns.size(); ++c) out << (c ? "," : "") << t.columns[c].name;
  out << '\n';
  for (std::size_t row = 0; row < t.rows; ++row) {
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      const TimeseriesColumn& column = t.columns[c];
      if (c) out << ',';
      if (column.is_text)
        out << column.text[row];
      else
        out << text::csv_number(column.numbers[row]);
    }
    out << '\n';
  }
}

void print_summary_table(std::ostream& out, const ScenarioResult& r) {
  const double mm = 1e3, deg = kDegPerRad;
  const std::ios::fmtflags flags = out.flags();
  const std::streamsize precision = out.precision();
  auto text = [&](const std::string& s, int width) { out << std::setw(width) << s; };
  auto left = [&](const std::string& s, int width) {
    out << std::left << std::setw(width) << s << std::right;
  };
  auto cell = [&](double v, double scale, int width, int digits) {
    if (!std::isfinite(v)) return text("-", width);
    out << std::setw(width) << std::fixed << std::setprecision(digits) << v * scale;
  };
  auto share = [&](const Coverage& c, int width) {
    if (c.estimated == 0) return text("-", width);
    cell(c.fraction(), 100.0, width - 1, 1);
    out << '%';
  };
  const std::size_t runs = r.runs.size();
  out << "scenario " << r.scenario << ": " << runs << " run(s) of " << r.duration_s
      << " s, scored:";
  for (const std::string& e : r.end_effectors) out << ' ' << e;
  const bool several = r.end_effectors.size() > 1;
  if (several) out << " (worst: per sample, the worse end effector)";
  if (r.duration_s <= r.scoring.converged_after_s)
    out << "\nwarning: the run ends at " << r.duration_s
        << " s, before the converged window starts (scoring.converged_after_s = "
        << r.scoring.converged_after_s
        << " s): converged statistics, times to converge and lost runs are empty";
  std::ostringstream after, lost_rule;
  after << "from " << r.scoring.converged_after_s << " s on";
  lost_rule << "lost: > " << r.scoring.lost_threshold_m * mm << " mm for > "
            << r.scoring.lost_after_s << " s";
  out << "\n";
  left("", 33);
  text("translation error, mm", 35);
  text("rotation error, deg", 35);
  text(after.str(), 19);
  out << "  " << lost_rule.str() << "\n";
  left("method", 20);
  left("end effector", 13);
  for (int k = 0; k < 2; ++k)
    for (const char* p : {"p1", "p25", "p50", "p75", "p99"}) text(p, 7);
  text("p50 mm", 10);
  text("conv. s", 9);
  text("lost runs", 13);
  out << "\n";
  // One row of pose statistics: an end effector's, or the worst.
  auto row = [&](const std::string& method, const std::string& ee, const ErrorStats& all,
                 const ErrorStats& converged, double convergence_s, std::size_t lost) {
    left(method, 20);
    left(ee, 13);
    const Percentiles& t = all.translation_m;
    for (double v : {t.p01, t.p25, t.p50, t.p75, t.p99}) cell(v, mm, 7, 1);
    const Percentiles& a = all.rotation_rad;
    for (double v : {a.p01, a.p25, a.p50, a.p75, a.p99}) cell(v, deg, 7, 2);
    cell(converged.translation_m.p50, mm, 10, 1);
    cell(convergence_s, 1.0, 9, 1);
    text(std::to_string(lost) + " of " + std::to_string(runs), 13);
    out << "\n";
  };
  for (const MethodResult& m : r.method_results) {
    const MethodSummary& s = m.summary;
    for (std::size_t e = 0; e < s.end_effectors.size(); ++e) {
      const EndEffectorSummary& es = s.end_effectors[e];
      row(e == 0 ? m.method : "", es.name, es.all, es.converged,
          median_convergence_s(es.time_to_converge_s),
          std::size_t(std::count_if(es.lost.begin(), es.lost.end(),
                                    [](const auto& l) { return l.has_value(); })));
    }
    if (several || s.end_effectors.empty())
      row(s.end_effectors.empty() ? m.method : "", "worst", s.all, s.converged,
          median_convergence_s(s), s.lost_runs());
  }

  // Consistency and the camera.
  out << "\n";
  left("", 20);
  text("truth within 2 sigma, all samples", 36);
  text("end effectors", 24);
  text("camera frame error: mm", 26);
  text("deg", 16);
  text("model error", 14);
  out << "\n";
  left("method", 20);
  text("angles", 12);
  text("biases", 12);
  text("camera", 12);
  text("position", 12);
  text("rotation", 12);
  for (int k = 0; k < 2; ++k) text("p50", 10), text("p99", k ? 8 : 14);
  text("p50 mm", 14);
  out << "\n";
  for (const MethodResult& m : r.method_results) {
    const ErrorStats& s = m.summary.all;
    left(m.method, 20);
    share(s.angle_coverage, 12);
    share(s.bias_coverage, 12);
    share(s.camera_offset_coverage, 12);
    share(s.end_effector_position_coverage, 12);
    share(s.end_effector_rotation_coverage, 12);
    cell(s.camera_translation_m.p50, mm, 10, 1);
    cell(s.camera_translation_m.p99, mm, 14, 1);
    cell(s.camera_rotation_rad.p50, deg, 10, 2);
    cell(s.camera_rotation_rad.p99, deg, 8, 2);
    // The link shifts the residuals show (TrackingHealth::model_error_std_m),
    // over the samples after the first image.
    std::vector<double> model_error;
    for (const RunResult& run : r.runs)
      for (const MethodRun& mr : run.methods)
        if (mr.method == m.method)
          for (const EstimateSample& e : mr.samples)
            if (e.health.state != TrackingHealth::State::kNoImage)
              model_error.push_back(e.health.model_error_std_m);
    cell(percentiles(model_error).p50, mm, 14, 1);  // "-" when there is none
    out << "\n";
    // The same from the converged window on: all samples mix the first
    // seconds' convergence, where a filter tends to be too sure, with the
    // steady state (docs/accuracy.md, "Coverage over time").
    const ErrorStats& c = m.summary.converged;
    left("  " + after.str(), 20);
    share(c.angle_coverage, 12);
    share(c.bias_coverage, 12);
    share(c.camera_offset_coverage, 12);
    share(c.end_effector_position_coverage, 12);
    share(c.end_effector_rotation_coverage, 12);
    out << "\n";
  }
  // The camera's share per virtual joint: the pooled one can sit in the band
  // while one axis is never covered.
  for (const MethodResult& m : r.method_results) {
    if (m.summary.all.camera_offset_coverage.estimated == 0) continue;
    out << m.method << ", camera within 2 sigma, x y z roll pitch yaw: all samples";
    for (const Coverage& c : m.summary.all.camera_axis_coverage) share(c, 7);
    out << "; " << after.str();
    for (const Coverage& c : m.summary.converged.camera_axis_coverage) share(c, 7);
    out << "\n";
  }
  // The links that fit the model least, by shift and by size: where to
  // look in the URDF. `size` is the figure ranked by its magnitude.
  auto ranked = [](const std::vector<LinkModelFit>& links, auto counted, auto size) {
    std::vector<LinkModelFit> out;
    std::copy_if(links.begin(), links.end(), std::back_inserter(out), counted);
    std::stable_sort(out.begin(), out.end(), [&](const LinkModelFit& a, const LinkModelFit& b) {
      return std::abs(size(a)) > std::abs(size(b));
    });
    return out;
  };
  for (const MethodResult& m : r.method_results) {
    const std::vector<LinkModelFit> pinned = ranked(
        m.links, [](const LinkModelFit& l) { return l.runs_pinned > 0; },
        [](const LinkModelFit& l) { return l.median_shift_m; });
    if (pinned.empty()) continue;
    out << m.method << ", links furthest from the model (pinned surface shift, median of the runs' "
        << "last estimates):";
    const char* separator = " ";
    if (pinned.front().median_shift_m < 0.05 / mm)  // would print 0.0 mm: name none
      out << " none, every pinned link within 0.1 mm";
    else
      for (std::size_t k = 0; k < pinned.size() && k < 3; ++k, separator = ", ")
        out << separator << pinned[k].link << " " << std::fixed << std::setprecision(1)
            << pinned[k].median_shift_m * mm << " mm";
    out << "; " << m.links.size() - pinned.size() << " of " << m.links.size()
        << " links never pinned\n";
  }
  for (const MethodResult& m : r.method_results) {
    const std::vector<LinkModelFit> scaled = ranked(
        m.links, [](const LinkModelFit& l) { return l.runs_scaled > 0; },
        [](const LinkModelFit& l) { return l.median_scale; });
    if (scaled.empty()) continue;
    out << m.method << ", links whose size differs most from the model (scale, median of the "
        << "runs' last estimates):";
    const char* separator = " ";
    for (std::size_t k = 0; k < scaled.size() && k < 3; ++k, separator = ", ")
      out << separator << scaled[k].link << " " << std::showpos << std::fixed
          << std::setprecision(1) << 100 * scaled[k].median_scale << std::noshowpos << "%";
    out << "; " << m.links.size() - scaled.size() << " of " << m.links.size()
        << " links never sized\n";
  }
  // The encoders' noise as the tracker measured it, in the units of the
  // configured encoder_noise_deg (encoder_noise_m for prismatic joints),
  // which the user compares it with.
  for (const MethodResult& m : r.method_results) {
    std::string line;
    for (const bool prismatic : {false, true}) {
      std::size_t smallest = r.joint_names.size(), largest = smallest;
      for (std::size_t j = 0; j < m.encoder_noise_rad.size() && j < r.joint_names.size(); ++j) {
        if (!std::isfinite(m.encoder_noise_rad[j]) || r.is_prismatic(j) != prismatic) continue;
        if (largest == r.joint_names.size() ||
            m.encoder_noise_rad[j] > m.encoder_noise_rad[largest])
          largest = j;
        if (smallest == r.joint_names.size() ||
            m.encoder_noise_rad[j] < m.encoder_noise_rad[smallest])
          smallest = j;
      }
      if (largest == r.joint_names.size()) continue;
      const double scale = prismatic ? mm : deg;
      const char* unit = prismatic ? " mm" : " deg";
      std::ostringstream part;
      part << std::fixed << std::setprecision(prismatic ? 3 : 4);
      if (largest == smallest)
        part << m.encoder_noise_rad[largest] * scale << unit << " (" << r.joint_names[largest]
             << ")";
      else
        part << "the largest " << m.encoder_noise_rad[largest] * scale << unit << " ("
             << r.joint_names[largest] << "), the smallest "
             << m.encoder_noise_rad[smallest] * scale << unit << " (" << r.joint_names[smallest]
             << ")";
      line += (line.empty() ? (prismatic ? "prismatic joints " : "") : "; prismatic joints ") +
              part.str();
    }
    if (line.empty()) continue;
    out << m.method
        << ", encoders' white noise as measured (median of the runs' last estimates): " << line
        << "\n";
  }
  // What the tracker did to get there: a share of hand shifts accepted near
  // 1 says a hand is longer or shorter along itself than its URDF or mesh.
  for (const MethodResult& m : r.method_results) {
    const HealthCounts& c = m.counts;
    if (c.acquisitions == 0 && c.refinements_accepted == 0 && c.hand_searches == 0) continue;
    out << m.method << ", counts summed over runs (" << c.runs << "): searches " << c.acquisitions
        << " (chains that took one's result " << c.chains_reacquired << "), refinement steps taken "
        << c.refinements_accepted << " (images with a motion they cannot see "
        << c.images_with_unseen_motion << "), joints unseen kept at their prior "
        << c.unseen_priors_kept << ", hand fits searched along the hand " << c.hand_searches
        << " (shifted " << c.hand_shifts_accepted;
    if (c.hand_searches > 0)
      out << ", " << std::lround(100.0 * double(c.hand_shifts_accepted) / double(c.hand_searches))
          << "%";
    out << ")\n";
  }
  out << "(-: not estimated, or no truth; end effectors: each position and rotation component\n"
         "of the reported pose against its reported sd; model error: the links' surface shift the\n"
         "depth residuals show, uncertainty.model_error)\n";

  // Which runs are lost.
  for (const MethodResult& m : r.method_results) {
    const MethodSummary& s = m.summary;
    if (s.lost_runs() == 0) continue;
    out << m.method << " lost " << s.lost_runs() << " of " << s.num_runs << ":";
    const char* run_separator = " ";
    for (std::size_t run = 0; run < s.num_runs; ++run) {
      if (!s.run_lost(run)) continue;
      out << run_separator << "run " << run;
      if (run < r.seeds.size()) out << " (seed " << r.seeds[run] << ")";
      out << ":";
      const char* separator = " ";
      for (const EndEffectorSummary& e : s.end_effectors)
        if (run < e.lost.size() && e.lost[run]) {
          out << separator << e.name << " from " << std::fixed << std::setprecision(1)
              << e.lost[run]->from_s << " s for " << e.lost[run]->duration_s << " s";
          if (const std::string notes = lost_span_notes(*e.lost[run]); !notes.empty())
            out << " (" << notes << ")";
          separator = ", ";
        }
      run_separator = "; ";
    }
    out << "\n";
  }
  out << "\n";
  out << std::left << std::setw(20) << "timing" << std::right;
  text("joint update us", 17);
  text("image update ms", 17);
  text("evaluations", 13);
  out << "\n" << std::left << std::setw(20) << "" << std::right;
  for (int k = 0; k < 2; ++k) text("p50", 8), text("p99", 9);
  text("per image", 13);
  out << "\n";
  for (const MethodResult& m : r.method_results) {
    out << std::left << std::setw(20) << m.method << std::right;
    cell(m.timing.joint_update_us.p50, 1.0, 8, 2);
    cell(m.timing.joint_update_us.p99, 1.0, 9, 2);
    cell(m.timing.image_update_ms.p50, 1.0, 8, 2);
    cell(m.timing.image_update_ms.p99, 1.0, 9, 2);
    cell(m.timing.evaluations_per_image, 1.0, 13, 0);
    out << "\n";
  }
  out << "\ninputs dropped (joint measurements outside the limits or not finite, images off "
         "the joint clock):";
  for (std::size_t i = 0; i < r.method_results.size(); ++i) {
    const TrackerStats d = dropped_inputs(r, i);
    out << (i ? "," : "") << " " << r.method_results[i].method << " "
        << d.joint_measurements_dropped << " / " << d.images_dropped_bad_stamp;
  }
  out << "\n";
  out.flags(flags);
  out.precision(precision);
}

std::vector<fs::path> write_run_outputs(const fs::path& dir, const ScenarioResult& r) {
  std::vector<fs::path> written{dir / "summary.json", dir / "timeseries.csv", dir / "report.html"};
  std::error_code ec;
  fs::create_directories(dir / "frames", ec);
  if (!fs::is_directory(dir / "frames"))
    throw InputError(dir.string() + ": cannot create the output folder");
  {
    std::ofstream json(dir / "summary.json");
    json << summary_json(r);
    if (!json) throw InputError((dir / "summary.json").string() + ": cannot write");
  }
  {
    std::ofstream csv(dir / "timeseries.csv");
    write_timeseries_csv(csv, r);
    if (!csv) throw InputError((dir / "timeseries.csv").string() + ": cannot write");
  }
  write_report_html(dir / "report.html", r);
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const std::string stem = "frame_" + std::to_string(i);
    written.push_back(dir / "frames" / (stem + "_observed.png"));
    write_depth_png_mm(written.back(), r.frames[i].observed);
    if (r.frames[i].estimate.empty()) continue;
    written.push_back(dir / "frames" / (stem + "_estimate.png"));
    write_depth_png_mm(written.back(), r.frames[i].estimate);
  }
  return written;
}

RunRecipe read_run_recipe(const fs::path& summary_json) {
  const std::string file = summary_json.string();
  std::ifstream in(summary_json);
  if (!in) throw InputError(file + ": cannot read");
  Json j;
  try {
    j = Json::parse(in);
  } catch (const Json::exception& e) {
    throw InputError(file + ": not JSON: " + e.what());
  }
  if (!j.is_object() || !j.contains("reproduce") || !j["reproduce"].is_object())
    throw InputError(file +
                     ": has no \"reproduce\" record (written by an older arttrack, or "
                     "not by arttrack run)");
  const Json& p = j["reproduce"];
  RunRecipe r;
  auto get = [&](const char* key, auto& value) {
    try {
      value = p.at(key).get<std::decay_t<decltype(value)>>();
    } catch (const Json::exception&) {
      throw InputError(file + ": key 'reproduce." + key + "' is missing or has the wrong type");
    }
  };
  get("version", r.version);
  get("scenario_file", r.scenario_file);
  get("scenario_dir", r.scenario_dir);
  get("overrides", r.overrides);
  get("scenario", r.scenario_yaml);
  get("tracker", r.tracker_yaml);
  get("seed", r.seed);
  get("runs", r.runs);
  get("methods", r.methods);
  get("realtime", r.realtime);
  if (r.runs < 1) throw InputError(file + ": key 'reproduce.runs' must be at least 1");
  if (r.seed > std::uint64_t(std::numeric_limits<long long>::max()))
    throw InputError(file + ": key 'reproduce.seed' must be below 2^63");
  return r;
}

Scenario scenario_from_recipe(const RunRecipe& recipe, const std::string& source) {
  const YamlDocument doc = load_yaml_string(recipe.scenario_yaml, source + " (reproduce.scenario)");
  const YamlDocument tracker =
      load_yaml_string(recipe.tracker_yaml, source + " (reproduce.tracker)");
  Scenario s = scenario_from_yaml(doc, recipe.scenario_dir, &tracker);
  s.source = recipe.scenario_file;
  s.overrides = recipe.overrides;
  return s;
}

}  // namespace arttrack::sim
