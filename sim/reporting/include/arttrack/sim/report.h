// A scenario run as one self-contained HTML page (DIR/report.html of
// `arttrack run`): inline SVG charts and CSS, depth frames embedded as PNG
// data URIs; no script, no network, no other file.
//
// The page shows: the scenario (name, file, duration, runs, seeds, methods)
// and a warning when the run ends before the converged window; a verdict per
// method (converged or not, time to converge, lost runs, share of samples
// worse than encoders only) and the best method never lost; box plots per
// method of the end-effector translation (mm) and rotation (degrees)
// errors, over all samples and after convergence, as the paper's Fig. 5-7
// (box p25-p75, ticks at p1, p50, p99; log axis when the values span more
// than about two decades); the translation error over time (run 0, or the
// median over runs); the tracker's health over time; the share of truths
// within 2 reported standard deviations over time (angles, biases, camera
// offset, end-effector position and rotation); full_fusion's
// estimated against true encoder bias per joint (estimate +- one standard
// deviation); the camera offset estimates against the true offset; the
// kept depth frames (observed depth in false colour, the estimate's
// silhouette edges in white); and the summary table (the numbers of
// summary.json) with the timings. The charts are drawn by the simulator's
// chart layer (internal/svg_chart.h), the sections by sim/reporting/src/report_*.cc.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "arttrack/sim/run_result.h"
#include "arttrack/sim/scoring.h"

namespace arttrack::sim {

// The report page as HTML text.
std::string report_html(const ScenarioResult& result);

// The method's 2-sigma consistency (scoring.h Coverage) of angles, biases,
// camera offset and end-effector poses in bins of bin_s from 0 s, every run
// pooled, from the runs' samples as the scorer takes them: summary.json's
// "consistency" as it changes over the run (the report's "Consistency over
// time"). The end-effector poses as ErrorStats::end_effector_position_coverage
// and end_effector_rotation_coverage count them: per end effector with a
// reported covariance, the three position and the three rotation components
// of EstimateSample::ee_error_vector against ee_std, pooled over the end
// effectors. A sample at or after the last bin's end counts in the last bin;
// bin_s <= 0: none.
struct ConsistencyBin {
  double from_s = 0;
  Coverage angles, biases, camera;
  Coverage end_effector_position, end_effector_rotation;
};
std::vector<ConsistencyBin> consistency_over_time(const ScenarioResult& result,
                                                  const std::string& method, double bin_s);

// Writes report_html(result) to `file`. Cannot write: InputError naming the file.
void write_report_html(const std::filesystem::path& file, const ScenarioResult& result);

}  // namespace arttrack::sim
