// Tracking a recorded dataset (dataset.h) offline: every method's tracker
// fed the dataset's joint readings and depth images in time order, scored
// against its ground truth if it has one, as `arttrack run` scores a
// simulated run (`arttrack track`).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "arttrack/sim/dataset.h"
#include "arttrack/sim/run_result.h"

namespace arttrack::sim {

struct TrackOptions {
  // Methods (empty: dataset.yaml's, else every method the data allows;
  // vision_only needs ground-truth angles for its start).
  std::vector<std::string> methods;
  // Tracker configuration (empty: the dataset's tracker.yaml, else
  // the built-in tracker/config/default.yaml). Its camera frame and delay are
  // the dataset's, its end effectors the ground truth's (if any); it runs
  // synchronously.
  std::optional<std::filesystem::path> tracker_config;
  // Depth frames kept for reports, evenly spread over the duration.
  int frames_to_keep = 4;
  // Also write an estimate.csv row every N joint readings (0: only at the
  // ground-truth rows, or without ground truth at every image arrival).
  int estimate_every_n_joints = 0;
  // Called for each warning (missing or unreadable frames, ...); may be empty.
  std::function<void(const std::string&)> warn;
};

// What tracking a dataset gave.
struct TrackResult {
  // The same structure `arttrack run` scores: one run, the ground-truth rows
  // as scored instants (no truth: runs[0].truth and the scores are empty).
  ScenarioResult result;
  int frames_missing = 0;      // missing or unreadable, skipped with a warning
  int truth_rows_skipped = 0;  // before the first joint reading
  std::vector<std::string> warnings;
};

// Tracks a dataset: per method one synchronous Tracker on the dataset's
// robot, fed the joint readings (at their time) and the depth images (at
// their arrival) in time order; at equal times joints first, then images,
// then the estimate is read. Vision only starts from the first ground-truth
// row's angles. Trackers are fed, scored and their frames kept as in
// `arttrack run` (method_trackers.h). Writes one estimate.csv row per method at every output
// instant into `estimate_csv` (if not null): time_s, method, per joint J
// J_rad, J_std_rad, J_bias_rad, J_bias_std_rad, the camera correction
// cam_x_m, cam_y_m, cam_z_m, cam_roll_rad, cam_pitch_rad, cam_yaw_rad, per end
// effector E: E_x, E_y, E_z, E_qw, E_qx, E_qy, E_qz (in the estimated camera
// frame). Errors: InputError (a method the data cannot run, joints of
// joints.csv and the URDF that differ, bad images as read_dataset_frame).
TrackResult track_dataset(const Dataset& dataset, const TrackOptions& options,
                          std::ostream* estimate_csv);

}  // namespace arttrack::sim
