// Recorded data: a folder holding what a tracker receives from a robot
// (encoder readings, depth images with their time stamps and arrival times),
// the camera and the nominal robot model, and optionally the ground truth.
// Written from a simulated scenario (export_scenario, `arttrack export`) or
// by a real robot's logger; tracked by track_dataset (dataset_tracking.h,
// `arttrack track`).
// docs/datasets.md documents the layout:
//
//   joints.csv        time_s,<joint>,...         encoder readings, rad
//   depth/            <stamp>.png                16-bit depth, depth_unit_m per count, 0 = no
//   return depth/index.csv   stamp_s,arrival_s,file     optional: arrival order and times
//   camera.yaml       width, height, fx, fy, cx, cy, frame, delay_s, depth_unit_m
//   robot.urdf        the nominal URDF (or robot.yaml: urdf, packages)
//   ground_truth.csv  optional: true angles, biases, end-effector poses in the camera frame
//   dataset.yaml      optional: name, seed, duration_s, methods, scoring
//   tracker.yaml      optional: the tracker configuration to use by default
//
// Times in seconds, angles in radians, poses T_camera_ee as x, y, z (m) and
// the unit quaternion qw, qx, qy, qz.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "arttrack/sim/run_result.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scoring.h"
#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

// camera.yaml: the depth camera's intrinsics and frame.
struct DatasetCamera {
  CameraIntrinsics intrinsics;
  // URDF link of the nominal camera frame (optical: z forward, x right, y down).
  std::string frame = "camera_optical_frame";
  // Constant delay from capture to stamp, s: the tracker applies an image
  // at stamp - delay_s (TrackerConfig::camera_delay_s). Unset: the tracker
  // configuration's.
  std::optional<double> delay_s;
  // Metres per PNG count (0.001: millimetres).
  double depth_unit_m = 0.001;
};

// One depth image of the dataset.
struct DatasetFrame {
  double stamp_s = 0;    // capture time (the image's time stamp)
  double arrival_s = 0;  // when it reached the tracker (>= stamp_s)
  std::filesystem::path file;
  // Where it is listed, for messages: "depth/index.csv:12" or the file.
  std::string where;
};

// A dataset read from its folder, checked (see load_dataset).
struct Dataset {
  std::filesystem::path dir;
  // dataset.yaml `name`, else the folder's name.
  std::string name;
  DatasetCamera camera;
  // The nominal URDF and the folders that resolve its package:// meshes.
  std::filesystem::path urdf;
  std::vector<std::string> mesh_search_paths;

  // Encoder readings: joints.csv columns after time_s, and per row its time
  // (strictly increasing) and readings (joint_time_s.size() x
  // joint_names.size(), row-major).
  std::vector<std::string> joint_names;
  std::vector<double> joint_time_s;
  std::vector<double> joint_readings_rad;

  // Depth images in arrival order (stamps increasing too).
  std::vector<DatasetFrame> frames;

  // ground_truth.csv (empty: none). Per row: angle_rad and bias_rad in
  // joint_names order (NaN where the file has no such columns),
  // T_camera_ee in truth_end_effectors order, camera_frame and
  // occluded_fraction if given (else true and NaN).
  std::vector<std::string> truth_end_effectors;
  std::vector<TruthSample> truth;
  bool truth_has_angles = false;
  bool truth_has_biases = false;

  // dataset.yaml (all optional): the run seed listed in summary.json, the
  // duration, the methods tracked by default, how methods are scored.
  std::optional<std::uint64_t> seed;
  std::optional<double> duration_s;
  std::vector<std::string> methods;
  ScoringOptions scoring;
  // tracker.yaml if the dataset has one.
  std::optional<std::filesystem::path> tracker_file;

  bool has_truth() const { return !truth.empty(); }
};

// Reads and checks a dataset folder (images are read later, one at a time,
// by read_dataset_frame). Errors name the file and line, or the file and
// key: a missing joints.csv or camera.yaml, no robot.urdf nor robot.yaml,
// a malformed number, a row of the wrong length, time stamps out of order or
// repeated (joints.csv, depth/index.csv, ground_truth.csv), an arrival before
// its stamp, image stamps going backwards in arrival order, a ground-truth
// column that is neither time_s, camera_frame, occluded_fraction, a joint of
// joints.csv (`J` or `J_bias`) nor a complete pose group `E_x, E_y, E_z,
// E_qw, E_qx, E_qy, E_qz`, a depth file name that is not a time stamp (when
// there is no index). `urdf_override` replaces the dataset's robot.
Dataset load_dataset(const std::filesystem::path& dir,
                     const std::optional<std::filesystem::path>& urdf_override = {});

// Reads one depth image in metres. A missing or unreadable file (not a PNG,
// truncated) is not an error: returns nullopt and sets `*problem` (tracking
// goes on without the frame). A readable image of the wrong size (not
// camera.yaml's) or in the wrong unit (median valid depth below 0.02 m or
// above 20 m at depth_unit_m: e.g. metres written as integers) is an
// InputError naming the file and what was expected.
std::optional<DepthImage> read_dataset_frame(const Dataset& dataset, const DatasetFrame& frame,
                                             std::string* problem);

// ---- export: a scenario's run as a dataset ----

// Receives a run's stream (RunOptions::sink) and writes it as a dataset into
// a folder: joints.csv, depth/*.png with depth/index.csv, ground_truth.csv.
// Writes run 0 only. Cannot create or write: InputError naming the path.
class DatasetWriter : public MeasurementSink {
 public:
  explicit DatasetWriter(const std::filesystem::path& dir);
  ~DatasetWriter() override;

  void begin_run(const RunStart& start) override;
  void joints(int run, double time_s, std::span<const double> readings_rad) override;
  void image(int run, double stamp_s, double arrival_s, const DepthImage& image) override;
  void truth(int run, const TruthSample& truth) override;

  // Flushes and closes the files; throws InputError if a write failed.
  void finish();

  const RunStart& start() const { return start_; }
  int joint_rows() const { return joint_rows_; }
  int frames() const { return frames_; }
  int truth_rows() const { return truth_rows_; }

 private:
  struct Files;
  std::filesystem::path dir_;
  std::unique_ptr<Files> files_;
  RunStart start_;
  int joint_rows_ = 0, frames_ = 0, truth_rows_ = 0;
};

// What export_scenario wrote.
struct ExportSummary {
  std::uint64_t run_seed = 0;
  int joint_rows = 0;
  int frames_captured = 0;
  int frames_delivered = 0;  // = depth images written
  int truth_rows = 0;
};

// Simulates run 0 of the scenario in `scenario_file` (with `overrides`, as
// load_scenario; seed >= 0 replaces its seed) and writes the dataset into
// `out_dir`: the stream exactly as the trackers of `arttrack run` receive it
// (corrupted encoders at the joint rate, corrupted delayed depth, stamps and
// arrival times), its ground truth at every scored instant, camera.yaml,
// robot.urdf (the nominal URDF with its meshes copied into meshes/),
// tracker.yaml (the run's tracker configuration, seed included) and
// dataset.yaml (run seed, duration, methods, scoring).
ExportSummary export_scenario(const std::filesystem::path& scenario_file,
                              const std::vector<std::string>& overrides, long long seed,
                              const std::filesystem::path& out_dir);

}  // namespace arttrack::sim
