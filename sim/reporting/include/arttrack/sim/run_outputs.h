// What `arttrack run` writes and prints from a ScenarioResult.
//
//   DIR/summary.json     per method (and per end effector): percentiles
//                        (p1, p25, p50, p75, p99) of the end-effector
//                        translation (m) and rotation (rad) errors over all
//                        samples and over the converged ones (time >=
//                        converged_after_s), the time to converge, lost runs,
//                        the camera frame's error, consistency, per-joint
//                        errors; timings of the tracker (see summary_json);
//   DIR/timeseries.csv   one row per (run, scored instant, method): errors,
//                        true and estimated angles and biases per joint;
//   DIR/report.html      the run report (report.h);
//   DIR/frames/          the kept depth frames as 16-bit PNG (millimetres):
//                        frame_<i>_observed.png and frame_<i>_estimate.png.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "arttrack/sim/run_result.h"
#include "arttrack/sim/scenario.h"

namespace arttrack::sim {

// The summary as JSON text:
//   {"scenario", "runs", "seeds", "duration_s", "end_effectors": [names],
//    "scoring": {"converged_after_s", "convergence_threshold_m",
//                "lost_threshold_m", "lost_after_s"},
//    "methods": {NAME: {
//        "translation_m": {"p1","p25","p50","p75","p99"}, "rotation_rad": {...},
//        "converged_translation_m": {...}, "converged_rotation_rad": {...},
//        "convergence_time_s",
//        "end_effectors": {E: {the same six keys, "lost_runs"}},
//        "lost": {"runs", "of", "list": [{"run", "seed", "end_effector",
//                                         "from_s", "duration_s"}]},
//        "camera": {"translation_m", "rotation_rad", "converged_translation_m",
//                   "converged_rotation_rad"} or null,
//        "consistency": {"angles", "biases", "camera_offset"},
//        "converged_consistency": {...},
//        "joints": {J: {"angle_abs_error_rad", "bias_abs_error_rad",
//                       "converged_angle_abs_error_rad", "converged_bias_abs_error_rad",
//                       "angle_within_2sigma", "bias_within_2sigma"}},
//        "links_model_error": {L: {"pinned_shift_m", "runs_pinned", "scale",
//                                  "runs_scaled"}},
//        "health_counts": {"runs", "acquisitions", "chains_reacquired",
//                          "refinements_accepted", "unseen_priors_kept",
//                          "images_with_unseen_motion",
//                          "hand_searches",
//                          "hand_shifts_accepted"}}},
//    "timing": {"joint_update_us": {"p50","p99"}, "image_update_ms": {"p50","p99"},
//               "evaluations_per_image"},
//    "dropped": {METHOD: {"joint_measurements", "images_bad_stamp"}},
//    "reproduce": {"version", "scenario_file", "scenario_dir", "overrides",
//                  "seed", "runs", "methods", "realtime", "scenario", "tracker"}
//                 or null}
// "dropped": the inputs the trackers dropped over all runs (TrackerStats:
// joint readings outside their limits or not finite, images off the joint
// clock). "reproduce": the RunRecipe ("scenario" and "tracker": the resolved
// YAML documents as text); null for a result not from a scenario.
// A method's top-level translation and rotation statistics are the pooled
// worst over the end effectors (per sample, the larger error; with one end
// effector, its own, as before end effectors had their own entries);
// "end_effectors" has each one's. convergence_time_s is the median over runs
// of the time after which the translation error stays below the threshold (a
// run that never converges counts as infinitely late); null if that median is
// infinite. "lost" counts the runs in which some end effector is lost
// (scoring.h lost_span) and lists each lost (run, end effector), with the
// share of the span the end effector was out of the camera's view
// (out_of_view_share; null: not known). "camera":
// the estimated camera frame against the true one relative to the robot base
// (null without camera truth). "consistency": the share of (sample,
// component) pairs whose truth lies within two reported standard deviations,
// over all samples (converged_: from converged_after_s on); null for a
// quantity the method does not estimate (standard deviation 0).
// "links_model_error" (only with uncertainty.model_error): per link with
// geometry, its pinned surface shift and its scale (TrackingHealth::links)
// in the runs' last estimates, the medians over the runs that pinned or
// sized it. "health_counts"
// (HealthCounts): the tracker's counters in each run's last estimate, summed
// over the runs (TrackingHealth: annealed searches, chains that took a
// search's result, Gauss-Newton steps taken, end-effector fits searched
// along the hand and those whose shift was accepted). Timing is
// that of full_fusion (else of the first method run): joint updates measured
// by the runner around each call, image updates as the tracker reports them.
// Non-finite numbers are written as null.
std::string summary_json(const ScenarioResult& result);

// One header line, then one row per (run, scored instant, method), in run,
// time and method order. Columns: time_s, run, method, camera_frame (0/1),
// occluded_fraction, per end effector E: translation_m_E, rotation_rad_E;
// per joint J: J_true_rad, J_est_rad, J_std_rad, J_true_bias_rad,
// J_est_bias_rad, J_bias_std_rad; then the estimated camera offset cam_x_m,
// cam_y_m, cam_z_m, cam_roll_rad, cam_pitch_rad, cam_yaw_rad and its
// standard deviations cam_x_std_m ... cam_yaw_std_rad; the camera frame's
// errors camera_translation_m, camera_rotation_rad; the true camera offset
// cam_true_x_m ... cam_true_yaw_rad (TruthSample::camera_offset); the health
// (health_state, health_explained_fraction, health_contradicted_fraction,
// health_abandoned_fraction, health_weakest_part_explained_fraction,
// health_unconfirmed_chains, health_model_error_std_m); then per end
// effector E, six components each (x_m, y_m, z_m, rx_rad, ry_rad, rz_rad):
// E_err_* (pose_error_vector, camera axes), E_std_* (the standard deviations
// the method reports for them) and E_correction_* (the end-effector fit's
// share of the pose, in its own axes). Full double precision; NaN as "nan"
// (also where there is no camera truth or no covariance).
void write_timeseries_csv(std::ostream& out, const ScenarioResult& result);

// timeseries.csv as columns, in its order and with its names: what
// write_timeseries_csv writes (it writes this table) and what the Python
// bindings return as arrays. `method` and `health_state` hold text; every
// other column numbers (run, camera_frame and health_unconfirmed_chains are
// whole numbers).
struct TimeseriesColumn {
  std::string name;
  std::vector<double> numbers;    // one per row, unless is_text
  std::vector<std::string> text;  // one per row, if is_text
  bool is_text = false;
};
struct TimeseriesTable {
  std::vector<TimeseriesColumn> columns;
  std::size_t rows = 0;
};
TimeseriesTable timeseries_table(const ScenarioResult& result);

// A compact table: per method and end effector (and the worst when there are
// several), p1/p25/p50/p75/p99 of translation (mm) and rotation (degrees)
// over all samples, the median after convergence, the convergence time and
// the lost runs ("2 of 10"); then per method the consistency (truth within
// two standard deviations: angles, biases, camera offset, end-effector
// positions and rotations; "-" when not estimated) and the camera frame's
// error; the lost runs by name; then the
// timings.
void print_summary_table(std::ostream& out, const ScenarioResult& result);

// Writes summary.json, timeseries.csv, report.html and frames/ into `dir`
// (created if missing) and returns every file written, in that order.
// Cannot create or write: InputError naming the path.
std::vector<std::filesystem::path> write_run_outputs(const std::filesystem::path& dir,
                                                     const ScenarioResult& result);

// The RunRecipe a summary.json records ("reproduce"); InputError naming the
// file and the key when it has none or it is malformed.
RunRecipe read_run_recipe(const std::filesystem::path& summary_json);

// The scenario a recipe describes: its resolved document and tracker
// configuration, relative paths against its scenario_dir; `source` (the
// summary.json) is named in messages.
Scenario scenario_from_recipe(const RunRecipe& recipe, const std::string& source);

}  // namespace arttrack::sim
