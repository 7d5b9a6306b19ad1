#include "arttrack/sim/scoring.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Sample times of two methods in the same run count as equal within this.
constexpr double kTimeMatch_s = 1e-6;

[[noreturn]] void fail(const std::string& what) { throw InputError("scoring: " + what); }

}  // namespace

PoseError pose_error(const Eigen::Isometry3d& T_cam_ee_est,
                     const Eigen::Isometry3d& T_cam_ee_true) {
  PoseError e;
  e.translation_m = (T_cam_ee_est.translation() - T_cam_ee_true.translation()).norm();
  const Eigen::Matrix3d R = T_cam_ee_est.linear().transpose() * T_cam_ee_true.linear();
  // q = (cos(a/2), sin(a/2) axis): atan2 keeps full precision at every angle;
  // |w| picks the angle in [0, pi] whatever the quaternion's sign.
  const Eigen::Quaterniond q(R);
  e.rotation_rad = 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
  return e;
}

double quantile_sorted(std::span<const double> sorted, double q) {
  if (sorted.empty()) return kNaN;
  const double h = double(sorted.size() - 1) * std::clamp(q, 0.0, 1.0);
  const std::size_t lo = std::size_t(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  const double a = sorted[lo], b = sorted[lo + 1], frac = h - double(lo);
  // Exact hits and equal neighbours return the value itself (no 0 * inf).
  if (frac == 0.0 || a == b) return a;
  return a + frac * (b - a);
}

Percentiles percentiles(std::span<const double> values) {
  Percentiles p;
  p.count = values.size();
  if (values.empty()) return p;
  std::vector<double> sorted(values.begin(), values.end());
  for (double& v : sorted)
    if (std::isnan(v)) v = std::numeric_limits<double>::infinity();
  std::sort(sorted.begin(), sorted.end());
  p.p01 = quantile_sorted(sorted, 0.01);
  p.p25 = quantile_sorted(sorted, 0.25);
  p.p50 = quantile_sorted(sorted, 0.50);
  p.p75 = quantile_sorted(sorted, 0.75);
  p.p99 = quantile_sorted(sorted, 0.99);
  double sum = 0.0;
  for (double v : sorted) sum += v;
  p.mean = sum / double(sorted.size());
  p.max = sorted.back();
  return p;
}

void ErrorTrace::add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad,
                     std::span<const double> bias_error_rad) {
  if (!std::isfinite(time_s) || (!time_s_.empty() && time_s < time_s_.back())) {
    std::ostringstream msg;
    msg << "sample time " << time_s << " s is not finite or earlier than the previous one";
    fail(msg.str());
  }
  for (std::span<const double> errors : {angle_error_rad, bias_error_rad})
    if (!errors.empty() && errors.size() != num_joints_)
      fail("per-joint errors have " + std::to_string(errors.size()) + " values, expected " +
           std::to_string(num_joints_));
  const int state = (angle_error_rad.empty() ? 0 : 1) | (bias_error_rad.empty() ? 0 : 2);
  if (joint_errors_state_ == -1) joint_errors_state_ = state;
  if (state != joint_errors_state_)
    fail("per-joint angle/bias errors must be given for every sample of a run or for none");
  time_s_.push_back(time_s);
  translation_m_.push_back(ee.translation_m);
  rotation_rad_.push_back(ee.rotation_rad);
  angle_error_rad_.insert(angle_error_rad_.end(), angle_error_rad.begin(), angle_error_rad.end());
  bias_error_rad_.insert(bias_error_rad_.end(), bias_error_rad.begin(), bias_error_rad.end());
}

std::optional<double> time_to_converge_s(const ErrorTrace& trace, double threshold_m) {
  const std::vector<double>& e = trace.translation_m();
  // Walk back from the end while the error is below the threshold (a NaN,
  // a lost estimate, is not below).
  std::size_t first_below = e.size();
  while (first_below > 0 && e[first_below - 1] < threshold_m) --first_below;
  if (first_below == e.size()) return std::nullopt;
  return trace.time_s()[first_below];
}

ReferenceComparison compare_with_reference(const ErrorTrace& trace, const ErrorTrace& reference,
                                           double from_time_s) {
  ReferenceComparison c;
  const std::vector<double>&ta = trace.time_s(), &tb = reference.time_s();
  std::size_t i = 0, k = 0;
  while (i < ta.size() && k < tb.size()) {
    if (ta[i] < tb[k] - kTimeMatch_s) {
      ++i;
    } else if (tb[k] < ta[i] - kTimeMatch_s) {
      ++k;
    } else {
      if (ta[i] >= from_time_s) {
        ++c.compared;
        // NaN (lost) is worse than any number; two lost are not worse.
        const double a = trace.translation_m()[i], b = reference.translation_m()[k];
        const double a_inf = std::isnan(a) ? std::numeric_limits<double>::infinity() : a;
        const double b_inf = std::isnan(b) ? std::numeric_limits<double>::infinity() : b;
        c.worse += a_inf > b_inf;
      }
      ++i, ++k;
    }
  }
  return c;
}

void ScoringOptions::validate() const {
  if (!(converged_after_s >= 0.0) || !std::isfinite(converged_after_s))
    fail("converged_after_s must be >= 0");
  if (!(convergence_threshold_m > 0.0) || !std::isfinite(convergence_threshold_m))
    fail("convergence_threshold_m must be > 0");
}

MethodScores::MethodScores(std::string method, std::vector<std::string> joint_names)
    : method_(std::move(method)), joint_names_(std::move(joint_names)) {}

void MethodScores::begin_run() { runs_.emplace_back(joint_names_.size()); }

void MethodScores::add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad,
                       std::span<const double> bias_error_rad) {
  if (runs_.empty()) begin_run();
  runs_.back().add(time_s, ee, angle_error_rad, bias_error_rad);
}

void MethodScores::add_run(ErrorTrace run) {
  if (run.num_joints() != joint_names_.size())
    fail("method '" + method_ + "': a run has " + std::to_string(run.num_joints()) +
         " joints, expected " + std::to_string(joint_names_.size()));
  runs_.push_back(std::move(run));
}

void MethodScores::merge(const MethodScores& other) {
  if (other.joint_names_ != joint_names_)
    fail("method '" + method_ + "': cannot pool runs with different joints");
  runs_.insert(runs_.end(), other.runs_.begin(), other.runs_.end());
}

namespace {

// Statistics over the samples at time >= from_s of every run.
ErrorStats stats_from(const std::vector<ErrorTrace>& runs, std::size_t num_joints, double from_s,
                      const std::vector<ErrorTrace>* reference) {
  ErrorStats s;
  std::vector<double> trans, rot;
  std::vector<std::vector<double>> angle(num_joints), bias(num_joints);
  bool any_angle = false, any_bias = false;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const ErrorTrace& run = runs[r];
    for (std::size_t i = 0; i < run.size(); ++i) {
      if (run.time_s()[i] < from_s) continue;
      trans.push_back(run.translation_m()[i]);
      rot.push_back(run.rotation_rad()[i]);
      for (std::size_t j = 0; j < num_joints; ++j) {
        if (run.has_angle_errors()) angle[j].push_back(std::abs(run.angle_error_rad(i, j)));
        if (run.has_bias_errors()) bias[j].push_back(std::abs(run.bias_error_rad(i, j)));
      }
    }
    any_angle |= run.has_angle_errors();
    any_bias |= run.has_bias_errors();
    if (reference) {
      const ReferenceComparison c = compare_with_reference(run, (*reference)[r], from_s);
      s.reference.compared += c.compared;
      s.reference.worse += c.worse;
    }
  }
  s.translation_m = percentiles(trans);
  s.rotation_rad = percentiles(rot);
  if (any_angle)
    for (const auto& v : angle) s.joint_angle_abs_error_rad.push_back(percentiles(v));
  if (any_bias)
    for (const auto& v : bias) s.joint_bias_abs_error_rad.push_back(percentiles(v));
  return s;
}

}  // namespace

MethodSummary MethodScores::summary(const ScoringOptions& options,
                                    const MethodScores* reference) const {
  options.validate();
  if (reference && reference->runs_.size() != runs_.size())
    fail("method '" + method_ + "' has " + std::to_string(runs_.size()) + " runs but reference '" +
         reference->method_ + "' has " + std::to_string(reference->runs_.size()));
  const std::vector<ErrorTrace>* ref = reference ? &reference->runs_ : nullptr;
  MethodSummary m;
  m.method = method_;
  m.joint_names = joint_names_;
  m.num_runs = runs_.size();
  m.all = stats_from(runs_, joint_names_.size(), -std::numeric_limits<double>::infinity(), ref);
  m.converged = stats_from(runs_, joint_names_.size(), options.converged_after_s, ref);
  for (const ErrorTrace& run : runs_)
    m.time_to_converge_s.push_back(time_to_converge_s(run, options.convergence_threshold_m));
  return m;
}

}  // namespace arttrack::sim
