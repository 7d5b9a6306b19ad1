// The sections of the run report (report.h), each writing its part of the
// page through the chart layer (svg_chart.h): report.cc assembles them in
// page order. Internal to arttrack_sim_reporting.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>

#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/run_result.h"

namespace arttrack::sim::report {

constexpr double kMm = 1e3;

// ---- shared by the sections (report.cc) ----

// Okabe-Ito colours (distinguishable with colour-blindness), one per method;
// `index` picks one for a method without its own.
std::string method_colour(const std::string& method, std::size_t index);

// The method's part of a run (nullptr if it was not run).
const MethodRun* method_run(const RunResult& run, const std::string& method);

// The method's index in r.methods (r.methods.size() if absent).
std::size_t method_index(const ScenarioResult& r, const std::string& method);

// "left_ee, right_ee".
std::string end_effector_list(const ScenarioResult& r);

// A line chart over the run's time axis (0 to the duration, "time, s"), the
// frame every over-time chart shares: `width` x `height` viewBox pixels.
chart::LineChart time_chart(const ScenarioResult& r, const std::string& id, double width,
                            double height, const std::string& y_label);

// ---- the sections, in page order ----

// report_tables.cc: per method converged or not, time to converge, lost
// runs, share worse than encoders only; the best method never lost.
void verdict_section(std::ostream& o, const ScenarioResult& r);

// report_errors.cc: box plots of the end-effector errors, the translation
// error over time, the tracker's health over time.
void box_section(std::ostream& o, const ScenarioResult& r);
void error_time_section(std::ostream& o, const ScenarioResult& r);
void health_section(std::ostream& o, const ScenarioResult& r);

// report_errors.cc: consistency_over_time (report.h) as a chart.
void consistency_time_section(std::ostream& o, const ScenarioResult& r);

// report_estimates.cc: full_fusion's encoder bias and every method's camera
// offset over time, each against the simulator's truth.
void bias_section(std::ostream& o, const ScenarioResult& r);
void camera_section(std::ostream& o, const ScenarioResult& r);

// report_frames.cc: the kept depth frames in false colour with the
// estimate's silhouette, as embedded PNG images.
void frames_section(std::ostream& o, const ScenarioResult& r);

// report_tables.cc: the summary tables (summary.json's numbers), lost runs
// and consistency, timings, and summary.json itself folded.
void table_section(std::ostream& o, const ScenarioResult& r);

}  // namespace arttrack::sim::report
