// Scoring estimates against ground truth, as the paper does: the
// end-effector pose of the estimate in the estimated camera frame against the
// true end-effector pose in the true camera frame, sampled at regular times,
// summarised per method by the 1st, 25th, 50th, 75th and 99th percentiles
// over the samples of a sequence, pooled over runs with different seeds (the
// paper's box plots over 10 runs).
//
// Every scored end effector has its own statistics, and a pooled "worst":
// per sample, the largest translation error over the end effectors (and,
// separately, the largest rotation error), so that a lost arm cannot hide
// behind a good one.
//
// Also scored: per-joint angle and bias errors; the estimated camera frame
// (relative to the robot base) against the true one; the time a method takes
// to converge; lost runs (an end effector off by more than a threshold for
// more than a while after the convergence window starts); how often a method
// is worse than a reference method (encoders only) at the same times; and
// its consistency: how often the truth lies within the two standard
// deviations the method reports.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack::sim {

// Error of one end-effector pose estimate.
struct PoseError {
  double translation_m = 0.0;  // Euclidean distance of the positions
  double rotation_rad = 0.0;   // angle of R_est^T R_true, in [0, pi]
};

// Error of T_cam_ee_est (end effector in the estimated camera frame) against
// T_cam_ee_true (in the true camera frame). The angle is computed from the
// quaternion of R_est^T R_true as 2 atan2(|v|, |w|), accurate near 0 and pi
// (acos of the trace loses half the digits near 0).
PoseError pose_error(const Eigen::Isometry3d& T_cam_ee_est, const Eigen::Isometry3d& T_cam_ee_true);

// The same error as the six components TrackerEstimate::T_camera_ee_covariance
// describes, in the camera frame's axes: position, estimate - truth (m), then
// the rotation vector of R_est R_true^T (rad; its norm is
// pose_error().rotation_rad).
using PoseErrorVector = Eigen::Matrix<double, 6, 1>;
PoseErrorVector pose_error_vector(const Eigen::Isometry3d& T_cam_ee_est,
                                  const Eigen::Isometry3d& T_cam_ee_true);

// The q-quantile (q in [0, 1]) of ascending `sorted` values by linear
// interpolation between order statistics, numpy's default ('linear',
// Hyndman-Fan type 7): h = (n - 1) q, x[floor h] + (h - floor h)
// (x[floor h + 1] - x[floor h]). NaN for no values.
double quantile_sorted(std::span<const double> sorted, double q);

// Summary of a set of values. All NaN when count is 0.
struct Percentiles {
  std::size_t count = 0;
  double p01 = std::numeric_limits<double>::quiet_NaN();
  double p25 = std::numeric_limits<double>::quiet_NaN();
  double p50 = std::numeric_limits<double>::quiet_NaN();
  double p75 = std::numeric_limits<double>::quiet_NaN();
  double p99 = std::numeric_limits<double>::quiet_NaN();
  double mean = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

// Percentiles (quantile_sorted) of unordered values. A NaN value (a lost
// estimate) counts as +infinity: the worst error.
Percentiles percentiles(std::span<const double> values);

// The six virtual camera joints (robot_model.h: x, y, z in metres, then
// roll, pitch, yaw in radians, T = Trans(x, y, z) Rx(roll) Ry(pitch) Rz(yaw))
// that give the transform T_nominal_corrected. Pitch in [-pi/2, pi/2];
// exact for |pitch| < pi/2.
using CameraOffset = Eigen::Matrix<double, 6, 1>;
CameraOffset camera_offset_of(const Eigen::Isometry3d& T_nominal_corrected);

// Camera frames of a robot model with virtual camera joints, relative to the
// robot base (the URDF root link), by the model's own forward kinematics.
// One instance per thread (it holds a kinematics workspace).
class CameraPoses {
 public:
  // Throws InputError if the model has no virtual camera joints.
  explicit CameraPoses(std::shared_ptr<const RobotModel> model);

  // The corrected camera frame at physical joint angles `angle_rad` (the
  // model's DOF order, virtual joints excluded) and camera offset `offset`.
  Eigen::Isometry3d camera(const Eigen::VectorXd& angle_rad, const CameraOffset& offset);
  // The camera offset that puts the corrected camera frame at
  // T_base_camera when the physical joints are at `angle_rad`:
  // camera_offset_of(T_base_nominal(angle_rad)^-1 T_base_camera).
  CameraOffset offset_to(const Eigen::VectorXd& angle_rad, const Eigen::Isometry3d& T_base_camera);

 private:
  std::shared_ptr<const RobotModel> model_;
  KinematicsState state_;
  Eigen::VectorXd q_;
};

// What one method got wrong at one scored instant, and how sure it said it
// was. Vectors left empty are unknown (no truth, or not reported); a
// standard deviation of 0 means "not estimated" (TrackerEstimate's
// convention).
struct ScoredSample {
  double time_s = 0;
  // One per end effector of the trace.
  std::vector<PoseError> end_effectors;
  // Per joint: estimate - truth, rad, and the reported standard deviation.
  std::vector<double> angle_error_rad, angle_std_rad;
  std::vector<double> bias_error_rad, bias_std_rad;
  // The estimated camera frame against the true one, both relative to the
  // robot base (nullopt: no camera truth).
  std::optional<PoseError> camera;
  // Virtual camera joints (CameraOffset order): estimate - truth, and the
  // reported standard deviation.
  std::vector<double> camera_offset_error, camera_offset_std;
  // Per end effector, six values each (end effector after end effector):
  // its pose_error_vector, and the standard deviations the method reports
  // for those components (the square roots of the diagonal of
  // TrackerEstimate::T_camera_ee_covariance).
  std::vector<double> end_effector_error, end_effector_std;
  // Per end effector: whether its true origin was in the camera's view
  // (in_camera_view); empty: not known. No image can correct an arm out of
  // view, so a lost span says how much of it was.
  std::vector<bool> end_effector_in_view;
};

// Whether a point in the camera's optical frame is in front of it and
// projects into the image (CameraIntrinsics: pixel (u, v) covers [u, u+1) x
// [v, v+1)). Whether something hides it is not considered.
bool in_camera_view(const Eigen::Vector3d& p_camera, const CameraIntrinsics& camera);

// The errors of one method in one run, in time order, for one or several end
// effectors. Every optional part of a sample (per-joint errors, standard
// deviations, camera) is all or nothing per trace: every sample has it or
// none does.
class ErrorTrace {
 public:
  explicit ErrorTrace(std::size_t num_joints = 0, std::size_t num_end_effectors = 1)
      : num_joints_(num_joints), num_end_effectors_(num_end_effectors) {}

  // Adds a sample. Throws InputError if its time is earlier than the
  // previous sample's or not finite, if it has the wrong number of end
  // effectors, joints or camera offset values, or if an optional part is
  // present in some samples and not others.
  void add(const ScoredSample& sample);
  // One end effector (the trace must have one): a pose error and optional
  // per-joint errors (estimate - truth per joint, rad; empty or num_joints
  // values).
  void add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad = {},
           std::span<const double> bias_error_rad = {});

  std::size_t size() const { return time_s_.size(); }
  std::size_t num_joints() const { return num_joints_; }
  std::size_t num_end_effectors() const { return num_end_effectors_; }
  const std::vector<double>& time_s() const { return time_s_; }
  // Per sample, the worst over the end effectors (the largest translation
  // error, and separately the largest rotation error; NaN, a lost estimate,
  // is the worst); with one end effector, its errors.
  const std::vector<double>& translation_m() const { return translation_m_; }
  const std::vector<double>& rotation_rad() const { return rotation_rad_; }
  // End effector e alone: its pose errors, nothing else.
  ErrorTrace end_effector(std::size_t e) const;

  bool has_angle_errors() const { return has(kAngleError); }
  bool has_bias_errors() const { return has(kBiasError); }
  bool has_angle_std() const { return has(kAngleStd); }
  bool has_bias_std() const { return has(kBiasStd); }
  bool has_camera() const { return has(kCamera); }
  bool has_camera_offset_errors() const { return has(kCameraOffsetError); }
  bool has_camera_offset_std() const { return has(kCameraOffsetStd); }
  // Error of joint j at sample i, rad (only if has_*_errors()).
  double angle_error_rad(std::size_t i, std::size_t j) const {
    return angle_error_rad_[i * num_joints_ + j];
  }
  double bias_error_rad(std::size_t i, std::size_t j) const {
    return bias_error_rad_[i * num_joints_ + j];
  }
  double angle_std_rad(std::size_t i, std::size_t j) const {
    return angle_std_rad_[i * num_joints_ + j];
  }
  double bias_std_rad(std::size_t i, std::size_t j) const {
    return bias_std_rad_[i * num_joints_ + j];
  }
  // The camera frame's errors per sample (empty unless has_camera()).
  const std::vector<double>& camera_translation_m() const { return camera_translation_m_; }
  const std::vector<double>& camera_rotation_rad() const { return camera_rotation_rad_; }
  // Virtual camera joint k (0..5) at sample i.
  double camera_offset_error(std::size_t i, std::size_t k) const {
    return camera_offset_error_[i * 6 + k];
  }
  double camera_offset_std(std::size_t i, std::size_t k) const {
    return camera_offset_std_[i * 6 + k];
  }
  // Component k (0..5, PoseErrorVector order) of end effector e's error at
  // sample i, and its reported standard deviation (only if
  // has_end_effector_errors() and has_end_effector_std()).
  bool has_end_effector_errors() const { return has(kEndEffectorError); }
  bool has_end_effector_std() const { return has(kEndEffectorStd); }
  double end_effector_error(std::size_t i, std::size_t e, std::size_t k) const {
    return ee_error_[(i * num_end_effectors_ + e) * 6 + k];
  }
  double end_effector_std(std::size_t i, std::size_t e, std::size_t k) const {
    return ee_std_[(i * num_end_effectors_ + e) * 6 + k];
  }
  // Whether end effector e was in view at sample i (only if has_in_view()).
  bool has_in_view() const { return has(kInView); }
  bool end_effector_in_view(std::size_t i, std::size_t e) const {
    return in_view_[i * num_end_effectors_ + e];
  }

 private:
  enum Part : unsigned {
    kAngleError = 1,
    kBiasError = 2,
    kAngleStd = 4,
    kBiasStd = 8,
    kCamera = 16,
    kCameraOffsetError = 32,
    kCameraOffsetStd = 64,
    kInView = 128,
    kEndEffectorError = 256,
    kEndEffectorStd = 512,
  };
  bool has(Part p) const { return parts_ != kUnknown && (parts_ & p); }
  static constexpr unsigned kUnknown = ~0u;

  std::size_t num_joints_, num_end_effectors_;
  std::vector<double> time_s_, translation_m_, rotation_rad_;
  std::vector<double> ee_translation_m_, ee_rotation_rad_;  // sample-major
  std::vector<double> angle_error_rad_, bias_error_rad_;    // sample-major
  std::vector<double> angle_std_rad_, bias_std_rad_;        // sample-major
  std::vector<double> camera_translation_m_, camera_rotation_rad_;
  std::vector<double> camera_offset_error_, camera_offset_std_;  // sample-major
  std::vector<double> ee_error_, ee_std_;                        // sample-major, 6 per EE
  std::vector<bool> in_view_;                                    // sample-major
  unsigned parts_ = kUnknown;  // Part bits, fixed by the first sample
};

// First sample time after which the translational error stays below
// threshold_m (strictly) to the end of the trace; nullopt if it never does
// (the last sample is not below, or the trace is empty).
std::optional<double> time_to_converge_s(const ErrorTrace& trace, double threshold_m);

// Sample-by-sample comparison with a reference method at the same times
// (matched within 1 microsecond; samples without a partner are skipped).
struct ReferenceComparison {
  std::size_t compared = 0;  // samples at common times
  std::size_t worse = 0;     // of those, translational error > reference's
  double share_worse() const {
    return compared ? double(worse) / compared : std::numeric_limits<double>::quiet_NaN();
  }
};
// Compares samples with time >= from_time_s.
ReferenceComparison compare_with_reference(const ErrorTrace& trace, const ErrorTrace& reference,
                                           double from_time_s = 0.0);

// How a summary is made.
struct ScoringOptions {
  // Samples earlier than this are left out of the "converged" statistics, s
  // (>= 0): the first seconds while a filter converges.
  double converged_after_s = 10.0;
  // Translational error below which a method counts as converged, m (> 0).
  double convergence_threshold_m = 0.01;
  // A run is lost for a method when an end effector's translational error
  // stays above lost_threshold_m (m, > 0) for more than lost_after_s (s,
  // > 0) at or after converged_after_s.
  double lost_threshold_m = 0.02;
  double lost_after_s = 1.0;

  void validate() const;
};

// A stretch of consecutive samples whose translational error is above the
// lost threshold.
struct LostSpan {
  double from_s = 0;      // its first sample
  double duration_s = 0;  // from its first to its last sample
  // Share of its samples in which the end effector was out of the camera's
  // view (ErrorTrace::end_effector_in_view), in [0, 1]; NaN when not known
  // (no view in the trace, or a trace of several end effectors).
  double out_of_view_share = std::numeric_limits<double>::quiet_NaN();
  // Every stretch of the trace that counts as lost, this one the first:
  // how many, and their durations summed (s). A run lost twice, or lost
  // again after it came back, says so.
  int stretches = 1;
  double total_s = 0;
};

// The first stretch of consecutive samples at time >= converged_after_s
// whose translational error is above lost_threshold_m (NaN, a lost
// estimate, is above) and that lasts more than lost_after_s, from its first
// sample to its last (a conservative measure: the error may have been above
// a little longer, between samples), with the count and total duration of
// every such stretch; nullopt if there is none. For a trace of several end
// effectors this looks at the worst per sample; use ErrorTrace::end_effector
// for one.
std::optional<LostSpan> lost_span(const ErrorTrace& trace, const ScoringOptions& options);

// "out of the camera's view for 40% of it" when some of the span was (the
// terminal's and the report's lost lists); "" when none was or not known.
std::string out_of_view_note(const LostSpan& span);

// "3 stretches, 12.4 s in all" when the run was lost more than once (the
// same lists); "" when the span is its only one.
std::string more_stretches_note(const LostSpan& span);

// The span's notes above that apply, joined by "; " (what the terminal's
// and the report's lost lists add to "from ... s for ... s"); "" if none.
std::string lost_span_notes(const LostSpan& span);

// The virtual camera joints' names, in CameraOffset order (translation, then
// rotation about the nominal camera frame's axes).
inline constexpr std::array<std::string_view, 6> kCameraOffsetAxes = {"x",    "y",     "z",
                                                                      "roll", "pitch", "yaw"};

// How often the truth lies within two reported standard deviations.
struct Coverage {
  // (sample, component) pairs whose reported standard deviation is not 0
  // (0: not estimated).
  std::size_t estimated = 0;
  // Of those, |estimate - truth| <= 2 standard deviations (a NaN error or
  // standard deviation is outside).
  std::size_t within = 0;
  // within / estimated; NaN when nothing was estimated.
  double fraction() const {
    return estimated ? double(within) / double(estimated)
                     : std::numeric_limits<double>::quiet_NaN();
  }
  void add(double error, double std);
  Coverage& operator+=(const Coverage& o) {
    estimated += o.estimated;
    within += o.within;
    return *this;
  }
};

// Statistics over a set of samples pooled over runs.
struct ErrorStats {
  Percentiles translation_m;
  Percentiles rotation_rad;
  // Per joint, of |estimate - truth|; empty if the traces have none.
  std::vector<Percentiles> joint_angle_abs_error_rad;
  std::vector<Percentiles> joint_bias_abs_error_rad;
  // Against the reference method, pooled over runs (compared = 0 without).
  ReferenceComparison reference;
  // The estimated camera frame against the true one (count 0 without camera
  // truth).
  Percentiles camera_translation_m;
  Percentiles camera_rotation_rad;
  // Consistency: true angles, biases and camera offset within two reported
  // standard deviations, over all joints (all six virtual joints), and per
  // joint (empty without standard deviations or truth).
  Coverage angle_coverage, bias_coverage, camera_offset_coverage;
  // camera_offset_coverage per virtual joint (kCameraOffsetAxes order): the
  // pooled share can sit in the band while one axis is never covered and the
  // other five always are (docs/accuracy.md, "The camera's axes").
  std::array<Coverage, 6> camera_axis_coverage;
  // The same of the end-effector poses (ScoredSample::end_effector_error):
  // the three position components, and the three rotation components, over
  // the end effectors of the traces (one end effector's alone in its
  // EndEffectorSummary). What a program that gates a grasp on the reported
  // pose uncertainty relies on.
  Coverage end_effector_position_coverage, end_effector_rotation_coverage;
  std::vector<Coverage> joint_angle_coverage, joint_bias_coverage;
};

// Statistics of one end effector of a method over all its runs: pose errors
// and the comparison with the reference only.
struct EndEffectorSummary {
  std::string name;
  ErrorStats all, converged;
  // Per run: time_to_converge_s at convergence_threshold_m (nullopt: never).
  std::vector<std::optional<double>> time_to_converge_s;
  // Per run: the stretch for which this end effector is lost (nullopt: not lost).
  std::vector<std::optional<LostSpan>> lost;
};

// Summary of one method over all its runs.
struct MethodSummary {
  std::string method;
  std::vector<std::string> joint_names;
  std::size_t num_runs = 0;
  // The pooled worst over the end effectors (ErrorTrace::translation_m):
  // with one end effector, its statistics. Per-joint, camera and
  // consistency statistics are here only.
  ErrorStats all;        // every sample
  ErrorStats converged;  // samples at time >= converged_after_s
  // Per run: time_to_converge_s of the worst (nullopt: never).
  std::vector<std::optional<double>> time_to_converge_s;
  // One per end effector, in the scores' order.
  std::vector<EndEffectorSummary> end_effectors;

  // Runs in which at least one end effector is lost.
  std::size_t lost_runs() const;
  bool run_lost(std::size_t run) const;
};

// Accumulates one method's errors over runs (one ErrorTrace per run).
class MethodScores {
 public:
  // joint_names: the joints per-joint errors refer to, in order;
  // end_effectors: the end effectors of each sample, in order (at least one).
  MethodScores(std::string method, std::vector<std::string> joint_names,
               std::vector<std::string> end_effectors = {"end_effector"});

  // Starts a new run (another seed); add() then appends to it.
  void begin_run();
  // Adds a sample to the current run (starting the first run if none); see
  // ErrorTrace::add.
  void add(const ScoredSample& sample);
  void add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad = {},
           std::span<const double> bias_error_rad = {});
  // Appends a whole run. Throws InputError if its joint or end-effector
  // count differs.
  void add_run(ErrorTrace run);
  // Pools another accumulator's runs of the same method into this one.
  // Throws InputError if the joint or end-effector names differ.
  void merge(const MethodScores& other);

  const std::string& method() const { return method_; }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  const std::vector<std::string>& end_effectors() const { return end_effectors_; }
  const std::vector<ErrorTrace>& runs() const { return runs_; }

  // Percentiles over all samples of all runs and over the converged ones,
  // per end effector and of the worst, times to converge, lost runs, and,
  // given a reference (e.g. encoders only) with the same runs in the same
  // order, the share of samples worse than it. Throws InputError for invalid
  // options or a reference with a different number of runs or end effectors.
  MethodSummary summary(const ScoringOptions& options,
                        const MethodScores* reference = nullptr) const;

 private:
  std::string method_;
  std::vector<std::string> joint_names_, end_effectors_;
  std::vector<ErrorTrace> runs_;
};

}  // namespace arttrack::sim
