// The vocabulary of a run: the stream a MeasurementSink sees (RunStart,
// joints, images, TruthSample) and what a run gives (RunResult per run,
// MethodResult per method, ScenarioResult over all runs). Written by the
// scenario runner (scenario_runner.h) and by dataset tracking
// (dataset_tracking.h), read by datasets, method trackers, the outputs and
// reports, sweeps and tuning.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "arttrack/sim/scoring.h"
#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/version.h"

namespace arttrack::sim {

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
  // Per scored end effector: its error as pose_error_vector (camera axes),
  // the standard deviations the method reports for those six components
  // (empty without a covariance), and the end-effector fit's share of the
  // pose (TrackerEstimate::ee_image_correction: its own axes, zero without
  // the fit).
  std::vector<PoseErrorVector> ee_error_vector, ee_std;
  std::vector<Eigen::Matrix<double, 6, 1>> ee_correction;
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
  // The robot this run simulated, where model_mismatch.random drew it: the
  // drawn origin changes (m, by joint) and shape scales (by link).
  std::map<std::string, double> drawn_link_lengths_m, drawn_shape_scales;
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

// How far one link of the tracker's model seems from the robot
// (TrackingHealth::links): its pinned surface shift in each run's last
// estimate, the median over the runs whose images pinned it; and its
// scale, the median over the runs whose images sized it.
struct LinkModelFit {
  std::string link;
  double median_shift_m = std::numeric_limits<double>::quiet_NaN();
  int runs_pinned = 0;
  double median_scale = std::numeric_limits<double>::quiet_NaN();
  int runs_scaled = 0;
};

// Per link with geometry, model order, from every run's last estimate that
// has the list (none without uncertainty.model_error); `method` indexes
// RunResult::methods.
std::vector<LinkModelFit> link_model_fits(const std::vector<RunResult>& runs, std::size_t method);

// Each encoder's white noise as the tracker measured it (TrackingHealth::
// encoder_noise_measured_rad) in each run's last estimate, the median over
// the runs, per physical joint in DOF order (NaN: no encoder); empty when
// no estimate has it. `method` indexes RunResult::methods.
std::vector<double> encoder_noise_medians_rad(const std::vector<RunResult>& runs,
                                              std::size_t method);

// The tracker's own counts of what it did to get there (TrackingHealth's
// counters: searches, Gauss-Newton steps, joints unseen (out of view or
// hidden) kept at their prior, images whose step had a motion they cannot
// see, the end-effector fit's search along each
// hand), summed over the runs' last estimates; `method` indexes
// RunResult::methods. A run without samples adds nothing.
struct HealthCounts {
  int runs = 0;  // runs counted
  long long acquisitions = 0, chains_reacquired = 0, refinements_accepted = 0;
  long long unseen_priors_kept = 0, images_with_unseen_motion = 0;
  long long hand_searches = 0, hand_shifts_accepted = 0;
};
HealthCounts health_counts(const std::vector<RunResult>& runs, std::size_t method);

// Everything about one method over all runs.
struct MethodResult {
  std::string method;
  // One ErrorTrace per run; one sample per scored instant with every scored
  // end effector's errors, per-joint angle and bias errors, the camera's and
  // the reported standard deviations.
  MethodScores scores;
  MethodSummary summary;
  MethodTiming timing;
  std::vector<LinkModelFit> links;        // link_model_fits
  HealthCounts counts;                    // health_counts
  std::vector<double> encoder_noise_rad;  // encoder_noise_medians_rad
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
  // Per joint_names entry: a prismatic joint, whose per-joint figures named
  // _rad (angles, biases, their errors and standard deviations, the encoder
  // noise measured) are metres.
  std::vector<char> prismatic;
  std::vector<std::string> end_effectors;  // scored
  ScoringOptions scoring;
  std::vector<RunResult> runs;
  std::vector<MethodResult> method_results;  // methods order
  std::vector<KeptFrame> frames;

  const MethodResult* method(const std::string& name) const;
  bool is_prismatic(std::size_t joint) const {
    return joint < prismatic.size() && prismatic[joint];
  }
};

// ScenarioResult::prismatic for `joint_names`, joints of `robot`.
std::vector<char> prismatic_joints(const RobotModel& robot,
                                   const std::vector<std::string>& joint_names);

}  // namespace arttrack::sim
