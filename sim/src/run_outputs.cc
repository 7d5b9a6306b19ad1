#include "arttrack/sim/run_outputs.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/report.h"
#include "arttrack/tracker/error.h"
#include "text_format.h"

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

}  // namespace

std::string summary_json(const ScenarioResult& r) {
  Json j;
  j["scenario"] = r.scenario;
  j["runs"] = r.runs.size();
  j["seeds"] = r.seeds;
  j["duration_s"] = r.duration_s;
  Json methods = Json::object();
  for (const MethodResult& m : r.method_results) {
    methods[m.method] = Json{
        {"translation_m", five(m.summary.all.translation_m)},
        {"rotation_rad", five(m.summary.all.rotation_rad)},
        {"converged_translation_m", five(m.summary.converged.translation_m)},
        {"converged_rotation_rad", five(m.summary.converged.rotation_rad)},
        {"convergence_time_s", number(median_convergence_s(m.summary))},
    };
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
  return j.dump(2) + "\n";
}

void write_timeseries_csv(std::ostream& out, const ScenarioResult& r) {
  out << "time_s,run,method,camera_frame,occluded_fraction";
  for (const std::string& e : r.end_effectors)
    out << ",translation_m_" << e << ",rotation_rad_" << e;
  for (const std::string& j : r.joint_names)
    out << ',' << j << "_true_rad," << j << "_est_rad," << j << "_true_bias_rad," << j
        << "_est_bias_rad";
  out << ",cam_x_m,cam_y_m,cam_z_m,cam_roll_rad,cam_pitch_rad,cam_yaw_rad\n";
  for (const RunResult& run : r.runs) {
    for (std::size_t i = 0; i < run.truth.size(); ++i) {
      const TruthSample& truth = run.truth[i];
      for (const MethodRun& m : run.methods) {
        const EstimateSample& s = m.samples[i];
        out << text::csv_number(truth.time_s) << ',' << run.run << ',' << m.method << ','
            << (truth.camera_frame ? 1 : 0) << ',' << text::csv_number(truth.occluded_fraction);
        for (const PoseError& e : s.ee_error)
          out << ',' << text::csv_number(e.translation_m) << ','
              << text::csv_number(e.rotation_rad);
        for (Eigen::Index j = 0; j < truth.angle_rad.size(); ++j)
          out << ',' << text::csv_number(truth.angle_rad[j]) << ','
              << text::csv_number(s.angle_rad[j]) << ',' << text::csv_number(truth.bias_rad[j])
              << ',' << text::csv_number(s.bias_rad[j]);
        for (int k = 0; k < 6; ++k) out << ',' << text::csv_number(s.camera_offset[k]);
        out << '\n';
      }
    }
  }
}

void print_summary_table(std::ostream& out, const ScenarioResult& r) {
  const double mm = 1e3, deg = 180.0 / M_PI;
  const std::ios::fmtflags flags = out.flags();
  const std::streamsize precision = out.precision();
  auto text = [&](const std::string& s, int width) { out << std::setw(width) << s; };
  auto cell = [&](double v, double scale, int width, int digits) {
    if (!std::isfinite(v)) return text("-", width);
    out << std::setw(width) << std::fixed << std::setprecision(digits) << v * scale;
  };
  out << "scenario " << r.scenario << ": " << r.runs.size() << " run(s) of " << r.duration_s
      << " s, scored:";
  for (const std::string& e : r.end_effectors) out << ' ' << e;
  std::ostringstream after;
  after << "from " << r.scoring.converged_after_s << " s on";
  out << "\n" << std::left << std::setw(20) << "" << std::right;
  text("translation error, mm", 35);
  text("rotation error, deg", 35);
  text(after.str(), 19);
  out << "\n" << std::left << std::setw(20) << "method" << std::right;
  for (int k = 0; k < 2; ++k)
    for (const char* p : {"p1", "p25", "p50", "p75", "p99"}) text(p, 7);
  text("p50 mm", 10);
  text("conv. s", 9);
  out << "\n";
  for (const MethodResult& m : r.method_results) {
    out << std::left << std::setw(20) << m.method << std::right;
    const Percentiles& t = m.summary.all.translation_m;
    for (double v : {t.p01, t.p25, t.p50, t.p75, t.p99}) cell(v, mm, 7, 1);
    const Percentiles& a = m.summary.all.rotation_rad;
    for (double v : {a.p01, a.p25, a.p50, a.p75, a.p99}) cell(v, deg, 7, 2);
    cell(m.summary.converged.translation_m.p50, mm, 10, 1);
    cell(median_convergence_s(m.summary), 1.0, 9, 1);
    out << "\n";
  }
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
  out.flags(flags);
  out.precision(precision);
}

void write_run_outputs(const fs::path& dir, const ScenarioResult& r) {
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
    write_depth_png_mm(dir / "frames" / (stem + "_observed.png"), r.frames[i].observed);
    if (!r.frames[i].estimate.empty())
      write_depth_png_mm(dir / "frames" / (stem + "_estimate.png"), r.frames[i].estimate);
  }
}

}  // namespace arttrack::sim
