// Runs a scenario: simulates the robot, corrupts its sensors, feeds every
// tracking method the same corrupted data in lockstep and scores each against
// the ground truth.
//
// Per run k (seed run_seed(scenario seed, k)): one simulator with the
// PERTURBED URDF (miscalibration, model mismatch), one Tracker per method
// built on the NOMINAL URDF, in synchronous mode. Trackers never see ground
// truth: they get corrupted encoder readings at the joint rate and corrupted
// depth images, stamped with their capture time, at their arrival time
// (latency, jitter, drops). Only vision_only gets the true initial
// configuration (its starting point is "given", as in the paper).
//
// Scoring (scoring.h, paper Sec. V): at every camera capture time (and every
// N joint steps if the scenario says so), each scored end effector's pose in
// the method's estimated camera frame against its true pose in the true
// camera frame; per joint, estimated minus true angle and bias (true bias:
// EncoderCorruption::bias_rad()); the estimated camera frame (the nominal
// model's forward kinematics at the estimated angles and camera offset)
// against the simulator's true camera, both relative to the robot base; and
// the reported standard deviations against these errors (consistency).
//
// The runner simulates and measures; feeding the trackers, scoring their
// estimates and keeping frames is method_trackers.h, shared with `arttrack
// track` (dataset.h).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scoring.h"
#include "arttrack/sim/sim_model.h"
#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/version.h"

namespace arttrack::sim {

// Where a run is, for progress reports.
struct RunProgress {
  int run = 0;   // 0-based
  int runs = 1;  // total
  double time_s = 0;
  double duration_s = 0;
};

struct TruthSample;

// What a MeasurementSink learns when a run starts.
struct RunStart {
  int run = 0;
  std::uint64_t seed = 0;                   // the run's seed
  unsigned long long tracker_seed = 0;      // TrackerConfig::seed of its trackers
  std::vector<std::string> encoder_joints;  // order of the readings
  CameraIntrinsics camera;                  // of the delivered images
  // Order of TruthSample's per-joint and per-end-effector values.
  std::vector<std::string> truth_joints, end_effectors;
};

// Sees a run's measurements exactly as its trackers receive them, and the
// ground truth they are scored against (to export a dataset).
class MeasurementSink {
 public:
  virtual ~MeasurementSink() = default;
  virtual void begin_run(const RunStart& start) {}
  // Encoder readings taken at time_s, RunStart::encoder_joints order, rad.
  virtual void joints(int run, double time_s, std::span<const double> readings_rad) {}
  // A depth image stamped stamp_s (capture), given to the trackers at
  // arrival_s: the first joint step at or after its arrival, right after
  // that step's readings.
  virtual void image(int run, double stamp_s, double arrival_s, const DepthImage& image) {}
  // Ground truth at a scored instant, after that step's readings and images.
  virtual void truth(int run, const TruthSample& truth) {}
};

struct RunOptions {
  // Number of runs (0: the scenario's `runs`).
  int runs = 0;
  // The scenario seed that run seeds derive from (-1: the scenario's `seed`).
  long long seed = -1;
  // Methods to run (empty: the scenario's `methods`).
  std::vector<std::string> methods;
  // Called about every simulated second (may be empty).
  std::function<void(const RunProgress&)> progress;
  // Depth frames kept for reports, evenly spread over run 0.
  int frames_to_keep = 4;
  // Sees every run's measurements and truth (may be null; not owned).
  MeasurementSink* sink = nullptr;
  // Depth delivered in whole millimetres, as a 16-bit PNG stores it
  // (quantise_depth_mm in dataset.h): a run then equals tracking its
  // exported dataset.
  bool quantise_depth_mm = false;
  // Real time: each run is simulated first and its measurements kept (at
  // most 4 GB, 110 s of a 640x480 camera; a longer run is refused before it
  // starts), then replayed: each joint step waits until its simulated time
  // has passed on the wall clock since the replay began, and the trackers
  // are asynchronous (TrackerConfig::asynchronous): image updates run on
  // their own threads while joint readings go on, as on a robot; images that
  // arrive while an update runs wait or are dropped (TrackerStats). Image
  // latencies are then measured (MethodRun::image_latency_ms). Simulating
  // first keeps the simulator's physics and full-mesh rendering off the
  // cores the trackers use, as a robot's camera is.
  bool realtime = false;
};

// The seed of run k of a scenario with seed `seed`: a SplitMix64 mix (so
// neighbouring runs get unrelated streams) cut to 53 bits (exact in JSON).
std::uint64_t run_seed(std::uint64_t seed, int run);

// The joint targets the simulator's servos follow in run `run` of
// `scenario` with seed `seed` (the scenario's `seed`, or --seed), for the
// joints of `model`: the motion run_scenario drives that run with.
JointTrajectory run_trajectory(const Scenario& scenario, const SimModel& model, std::uint64_t seed,
                               int run);

// Ground truth at one scored instant.
struct TruthSample {
  double time_s = 0;
  // Scored at a camera capture (else: an every-N-joint-steps sample).
  bool camera_frame = false;
  // True angles and encoder biases, rad, ScenarioResult::joint_names order.
  Eigen::VectorXd angle_rad, bias_rad;
  // Scored end effectors in the TRUE camera frame (ScenarioResult::end_effectors order).
  std::vector<Eigen::Isometry3d> T_camera_ee;
  // The true camera frame relative to the robot base (the URDF root link),
  // and the camera offset (virtual camera joints, scoring.h CameraOffset)
  // that puts the tracker's nominal model's camera there at the true angles:
  // the offset a method should estimate. Unknown (nullopt, offset 0) in
  // datasets without camera truth.
  std::optional<Eigen::Isometry3d> T_base_camera;
  CameraOffset camera_offset = CameraOffset::Zero();
  // Share of the robot's pixels hidden by something else in front of it:
  // (robot pixels of the robot-alone render where the full scene is nearer)
  // / (robot pixels of the robot-alone render). NaN where not rendered (not
  // a delivered camera frame, or a scenario that moves no occluder: the
  // robot-alone render costs as much as the image) or where no robot pixel
  // is in view. A
  // robot pixel without return in the full scene (something nearer than the
  // near plane) counts as hidden.
  double occluded_fraction = std::numeric_limits<double>::quiet_NaN();
};

// One method's estimate at a scored instant.
struct EstimateSample {
  Eigen::VectorXd angle_rad, angle_std_rad;  // ScenarioResult::joint_names order
  Eigen::VectorXd bias_rad, bias_std_rad;
  // Virtual camera joints: x, y, z (m), roll, pitch, yaw (rad), and their
  // standard deviations (0: not estimated).
  CameraOffset camera_offset = CameraOffset::Zero();
  CameraOffset camera_offset_std = CameraOffset::Zero();
  // Scored end effectors in the ESTIMATED camera frame, and their errors.
  std::vector<Eigen::Isometry3d> T_camera_ee;
  std::vector<PoseError> ee_error;
  // The estimated camera frame against TruthSample::T_base_camera (NaN
  // without camera truth).
  PoseError camera_error{std::numeric_limits<double>::quiet_NaN(),
                         std::numeric_limits<double>::quiet_NaN()};
  // The tracker's own verdict on its newest image (TrackerEstimate::health).
  TrackingHealth health;
};

// One method in one run.
struct MethodRun {
  std::string method;
  // One per RunResult::truth sample, same order.
  std::vector<EstimateSample> samples;
  // Wall time of every add_joint_measurement call, microseconds.
  std::vector<double> joint_update_us;
  // The tracker's counters, image update times among them.
  TrackerStats stats;
  // Real time only: per applied image, wall time from its capture (its stamp
  // on the run's wall clock) until the estimate included it, ms.
  std::vector<double> image_latency_ms;
};

// One run.
struct RunResult {
  int run = 0;
  std::uint64_t seed = 0;
  std::vector<TruthSample> truth;
  std::vector<MethodRun> methods;  // ScenarioResult::methods order
  int frames_captured = 0;
  int frames_delivered = 0;
};

// A depth frame kept for reports: what the camera delivered and what the
// estimate of `estimate_method` renders right after the tracker took it.
struct KeptFrame {
  int run = 0;
  double stamp_s = 0;    // capture time
  double arrival_s = 0;  // when it reached the trackers
  DepthImage observed;   // the corrupted image, camera resolution
  std::string estimate_method;
  DepthImage estimate;  // the nominal robot at the estimate, same camera, 0 = no robot
};

// Timings of one method, pooled over runs.
struct MethodTiming {
  Percentiles joint_update_us;
  Percentiles image_update_ms;
  // Likelihood evaluations per applied image (mean; 0 without images).
  double evaluations_per_image = 0;
  // Real time only (else empty): MethodRun::image_latency_ms pooled over runs.
  Percentiles image_latency_ms;
};

// Everything about one method over all runs.
struct MethodResult {
  std::string method;
  // One ErrorTrace per run; one sample per scored instant with every scored
  // end effector's errors, per-joint angle and bias errors, the camera's and
  // the reported standard deviations.
  MethodScores scores;
  MethodSummary summary;
  MethodTiming timing;
};

// What reproduces a run (summary.json "reproduce"; arttrack rerun): the
// program's version, the scenario as resolved (Scenario::source, dir,
// overrides, resolved_yaml, tracker_document as YAML) and the options as
// resolved.
struct RunRecipe {
  std::string version = ARTTRACK_VERSION;
  std::string scenario_file;
  std::string scenario_dir;
  std::vector<std::string> overrides;
  std::string scenario_yaml;
  std::string tracker_yaml;
  std::uint64_t seed = 0;  // the scenario seed the runs' seeds derive from
  int runs = 0;
  std::vector<std::string> methods;
  bool realtime = false;
};

struct ScenarioResult {
  std::string scenario;  // Scenario::name
  std::string source;    // the scenario file
  RunRecipe recipe;
  double duration_s = 0;
  std::vector<std::uint64_t> seeds;  // per run
  std::vector<std::string> methods;
  // Physical joints in the tracker model's order (per-joint vectors).
  std::vector<std::string> joint_names;
  std::vector<std::string> end_effectors;  // scored
  ScoringOptions scoring;
  std::vector<RunResult> runs;
  std::vector<MethodResult> method_results;  // methods order
  std::vector<KeptFrame> frames;

  const MethodResult* method(const std::string& name) const;
};

// Runs the scenario. Throws InputError for bad options (unknown method,
// runs < 1) or a scenario the simulator or tracker rejects.
ScenarioResult run_scenario(const Scenario& scenario, const RunOptions& options = {});

}  // namespace arttrack::sim
