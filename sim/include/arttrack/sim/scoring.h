// Scoring estimates against ground truth, as the paper does: the
// end-effector pose of the estimate in the estimated camera frame against the
// true end-effector pose in the true camera frame, sampled at regular times,
// summarised per method by the 1st, 25th, 50th, 75th and 99th percentiles
// over the samples of a sequence, pooled over runs with different seeds (the
// paper's box plots over 10 runs).
//
// Also scored: per-joint angle and bias errors, the time a method takes to
// converge, and how often it is worse than a reference method (encoders
// only) at the same times.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

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

// The errors of one method in one run, in time order. Per-joint errors are
// all or nothing per trace: every sample has them (num_joints values) or
// none does.
class ErrorTrace {
 public:
  explicit ErrorTrace(std::size_t num_joints = 0) : num_joints_(num_joints) {}

  // Adds a sample at time_s. angle_error_rad and bias_error_rad (estimate -
  // truth per joint, rad) are empty or have num_joints values. Throws
  // InputError if time_s is earlier than the previous sample or not finite,
  // or if the per-joint errors are present in some samples and not others.
  void add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad = {},
           std::span<const double> bias_error_rad = {});

  std::size_t size() const { return time_s_.size(); }
  std::size_t num_joints() const { return num_joints_; }
  const std::vector<double>& time_s() const { return time_s_; }
  const std::vector<double>& translation_m() const { return translation_m_; }
  const std::vector<double>& rotation_rad() const { return rotation_rad_; }
  bool has_angle_errors() const { return !angle_error_rad_.empty(); }
  bool has_bias_errors() const { return !bias_error_rad_.empty(); }
  // Error of joint j at sample i, rad (only if has_*_errors()).
  double angle_error_rad(std::size_t i, std::size_t j) const {
    return angle_error_rad_[i * num_joints_ + j];
  }
  double bias_error_rad(std::size_t i, std::size_t j) const {
    return bias_error_rad_[i * num_joints_ + j];
  }

 private:
  std::size_t num_joints_;
  std::vector<double> time_s_, translation_m_, rotation_rad_;
  std::vector<double> angle_error_rad_, bias_error_rad_;  // sample-major
  int joint_errors_state_ = -1;  // -1 unknown, then bit 0 angles, bit 1 biases
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

  void validate() const;
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
};

// Summary of one method over all its runs.
struct MethodSummary {
  std::string method;
  std::vector<std::string> joint_names;
  std::size_t num_runs = 0;
  ErrorStats all;        // every sample
  ErrorStats converged;  // samples at time >= converged_after_s
  // Per run: time_to_converge_s at convergence_threshold_m (nullopt: never).
  std::vector<std::optional<double>> time_to_converge_s;
};

// Accumulates one method's errors over runs (one ErrorTrace per run).
class MethodScores {
 public:
  // joint_names: the joints per-joint errors refer to, in order.
  MethodScores(std::string method, std::vector<std::string> joint_names);

  // Starts a new run (another seed); add() then appends to it.
  void begin_run();
  // Adds a sample to the current run (starting the first run if none); see
  // ErrorTrace::add.
  void add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad = {},
           std::span<const double> bias_error_rad = {});
  // Appends a whole run. Throws InputError if its joint count differs.
  void add_run(ErrorTrace run);
  // Pools another accumulator's runs of the same method into this one.
  // Throws InputError if the joint names differ.
  void merge(const MethodScores& other);

  const std::string& method() const { return method_; }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  const std::vector<ErrorTrace>& runs() const { return runs_; }

  // Percentiles over all samples of all runs and over the converged ones,
  // times to converge, and, given a reference (e.g. encoders only) with the
  // same runs in the same order, the share of samples worse than it. Throws
  // InputError for invalid options or a reference with a different number
  // of runs.
  MethodSummary summary(const ScoringOptions& options,
                        const MethodScores* reference = nullptr) const;

 private:
  std::string method_;
  std::vector<std::string> joint_names_;
  std::vector<ErrorTrace> runs_;
};

}  // namespace arttrack::sim
