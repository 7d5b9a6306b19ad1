// What `arttrack run` writes and prints from a ScenarioResult.
//
//   DIR/summary.json     per method: percentiles (p1, p25, p50, p75, p99) of
//                        the end-effector translation (m) and rotation (rad)
//                        errors over all samples and over the converged ones
//                        (time >= converged_after_s), and the time to
//                        converge; timings of the tracker (see summary_json);
//   DIR/timeseries.csv   one row per (run, scored instant, method): errors,
//                        true and estimated angles and biases per joint;
//   DIR/frames/          the kept depth frames as 16-bit PNG (millimetres):
//                        frame_<i>_observed.png and frame_<i>_estimate.png.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

#include "arttrack/sim/scenario_runner.h"

namespace arttrack::sim {

// The summary as JSON text:
//   {"scenario", "runs", "seeds", "duration_s",
//    "methods": {NAME: {"translation_m": {"p1","p25","p50","p75","p99"},
//                       "rotation_rad": {...}, "converged_translation_m": {...},
//                       "converged_rotation_rad": {...}, "convergence_time_s"}},
//    "timing": {"joint_update_us": {"p50","p99"}, "image_update_ms": {"p50","p99"},
//               "evaluations_per_image"}}
// convergence_time_s is the median over runs of the time after which the
// translation error stays below the threshold (a run that never converges
// counts as infinitely late); null if that median is infinite. Timing is that
// of full_fusion (else of the first method run): joint updates measured by
// the runner around each call, image updates as the tracker reports them.
// Non-finite numbers are written as null.
std::string summary_json(const ScenarioResult& result);

// One header line, then one row per (run, scored instant, method), in run,
// time and method order. Columns: time_s, run, method, camera_frame (0/1),
// occluded_fraction, per end effector E: translation_m_E, rotation_rad_E;
// per joint J: J_true_rad, J_est_rad, J_true_bias_rad, J_est_bias_rad; then
// the estimated camera offset cam_x_m, cam_y_m, cam_z_m, cam_roll_rad,
// cam_pitch_rad, cam_yaw_rad. Full double precision; NaN as "nan".
void write_timeseries_csv(std::ostream& out, const ScenarioResult& result);

// A compact table: per method, p1/p25/p50/p75/p99 of translation (mm) and
// rotation (degrees) over all samples, the median after convergence and the
// convergence time; then the timings.
void print_summary_table(std::ostream& out, const ScenarioResult& result);

// Writes summary.json, timeseries.csv and frames/ into `dir` (created if
// missing). Cannot create or write: InputError naming the path.
void write_run_outputs(const std::filesystem::path& dir, const ScenarioResult& result);

}  // namespace arttrack::sim
