#include "arttrack/sim/scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/kinematics.h"

namespace arttrack::sim {
namespace {

// Sample times of two methods in the same run count as equal within this.
constexpr double kTimeMatch_s = 1e-6;

[[noreturn]] void fail(const std::string& what) { throw InputError("scoring: " + what); }

// The larger error; NaN (a lost estimate) is worse than any number.
double worse_of(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return kNaN;
  return std::max(a, b);
}

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

PoseErrorVector pose_error_vector(const Eigen::Isometry3d& T_cam_ee_est,
                                  const Eigen::Isometry3d& T_cam_ee_true) {
  PoseErrorVector v;
  v.head<3>() = T_cam_ee_est.translation() - T_cam_ee_true.translation();
  // Through the quaternion, as pose_error: accurate near 0; the angle in
  // [0, pi] whatever the quaternion's sign.
  Eigen::Quaterniond q(T_cam_ee_est.linear() * T_cam_ee_true.linear().transpose());
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  const double angle = 2.0 * std::atan2(s, q.w());
  v.tail<3>() = s > 0 ? Eigen::Vector3d(q.vec() * (angle / s)) : Eigen::Vector3d(2.0 * q.vec());
  return v;
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

void ErrorTrace::add(const ScoredSample& x) {
  if (!std::isfinite(x.time_s) || (!time_s_.empty() && x.time_s < time_s_.back())) {
    std::ostringstream msg;
    msg << "sample time " << x.time_s << " s is not finite or earlier than the previous one";
    fail(msg.str());
  }
  if (num_end_effectors_ == 0) fail("a trace needs at least one end effector");
  if (x.end_effectors.size() != num_end_effectors_)
    fail("a sample has " + std::to_string(x.end_effectors.size()) + " end effectors, expected " +
         std::to_string(num_end_effectors_));
  struct Optional {
    const std::vector<double>* values;
    std::size_t expected;
    Part part;
    const char* what;  // for the error message
  };
  const char* const kJoints = "per-joint errors";
  const char* const kCameraOffset = "camera offset values";
  const char* const kEndEffectors = "end-effector pose errors (6 per end effector)";
  const Optional parts[] = {
      {&x.angle_error_rad, num_joints_, kAngleError, kJoints},
      {&x.bias_error_rad, num_joints_, kBiasError, kJoints},
      {&x.angle_std_rad, num_joints_, kAngleStd, kJoints},
      {&x.bias_std_rad, num_joints_, kBiasStd, kJoints},
      {&x.camera_offset_error, 6, kCameraOffsetError, kCameraOffset},
      {&x.camera_offset_std, 6, kCameraOffsetStd, kCameraOffset},
      {&x.end_effector_error, 6 * num_end_effectors_, kEndEffectorError, kEndEffectors},
      {&x.end_effector_std, 6 * num_end_effectors_, kEndEffectorStd, kEndEffectors}};
  unsigned present = x.camera ? unsigned(kCamera) : 0u;
  if (!x.end_effector_in_view.empty()) {
    if (x.end_effector_in_view.size() != num_end_effectors_)
      fail("a sample says whether " + std::to_string(x.end_effector_in_view.size()) +
           " end effectors are in view, expected " + std::to_string(num_end_effectors_));
    present |= kInView;
  }
  for (const Optional& o : parts) {
    if (o.values->empty()) continue;
    if (o.values->size() != o.expected)
      fail(std::string(o.what) + " have " + std::to_string(o.values->size()) +
           " values, expected " + std::to_string(o.expected));
    present |= o.part;
  }
  if (parts_ == kUnknown) parts_ = present;
  if (present != parts_)
    fail(
        "per-joint angle/bias errors, standard deviations, camera errors, end-effector pose "
        "errors and whether the end effectors are in view must be given for every sample of a "
        "run or for none");

  time_s_.push_back(x.time_s);
  // The worst of the end effectors; a NaN (a lost estimate) is the worst.
  double worst_t = -kInf, worst_r = -kInf;
  for (const PoseError& e : x.end_effectors) {
    ee_translation_m_.push_back(e.translation_m);
    ee_rotation_rad_.push_back(e.rotation_rad);
    worst_t = worse_of(worst_t, e.translation_m);
    worst_r = worse_of(worst_r, e.rotation_rad);
  }
  translation_m_.push_back(worst_t);
  rotation_rad_.push_back(worst_r);
  auto append = [](std::vector<double>& to, const std::vector<double>& from) {
    to.insert(to.end(), from.begin(), from.end());
  };
  append(angle_error_rad_, x.angle_error_rad);
  append(bias_error_rad_, x.bias_error_rad);
  append(angle_std_rad_, x.angle_std_rad);
  append(bias_std_rad_, x.bias_std_rad);
  append(camera_offset_error_, x.camera_offset_error);
  append(camera_offset_std_, x.camera_offset_std);
  append(ee_error_, x.end_effector_error);
  append(ee_std_, x.end_effector_std);
  if (x.camera) {
    camera_translation_m_.push_back(x.camera->translation_m);
    camera_rotation_rad_.push_back(x.camera->rotation_rad);
  }
  in_view_.insert(in_view_.end(), x.end_effector_in_view.begin(), x.end_effector_in_view.end());
}

bool in_camera_view(const Eigen::Vector3d& p, const CameraIntrinsics& camera) {
  if (!(p.z() > 0)) return false;
  const double u = camera.fx * p.x() / p.z() + camera.cx;
  const double v = camera.fy * p.y() / p.z() + camera.cy;
  return u >= 0 && u < camera.width && v >= 0 && v < camera.height;
}

void ErrorTrace::add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad,
                     std::span<const double> bias_error_rad) {
  ScoredSample x;
  x.time_s = time_s;
  x.end_effectors = {ee};
  x.angle_error_rad.assign(angle_error_rad.begin(), angle_error_rad.end());
  x.bias_error_rad.assign(bias_error_rad.begin(), bias_error_rad.end());
  add(x);
}

ErrorTrace ErrorTrace::end_effector(std::size_t e) const {
  if (e >= num_end_effectors_)
    fail("end effector " + std::to_string(e) + " of a trace of " +
         std::to_string(num_end_effectors_));
  ErrorTrace t(num_joints_, 1);
  t.parts_ = 0;
  t.time_s_ = time_s_;
  for (std::size_t i = 0; i < size(); ++i) {
    t.translation_m_.push_back(ee_translation_m_[i * num_end_effectors_ + e]);
    t.rotation_rad_.push_back(ee_rotation_rad_[i * num_end_effectors_ + e]);
  }
  t.ee_translation_m_ = t.translation_m_;
  t.ee_rotation_rad_ = t.rotation_rad_;
  if (has_in_view()) {
    t.parts_ |= kInView;
    for (std::size_t i = 0; i < size(); ++i) t.in_view_.push_back(end_effector_in_view(i, e));
  }
  const auto copy_components = [&](Part part, const std::vector<double>& from,
                                   std::vector<double>& to) {
    if (!has(part)) return;
    t.parts_ |= part;
    for (std::size_t i = 0; i < size(); ++i) {
      const auto first = from.begin() + std::ptrdiff_t((i * num_end_effectors_ + e) * 6);
      to.insert(to.end(), first, first + 6);
    }
  };
  copy_components(kEndEffectorError, ee_error_, t.ee_error_);
  copy_components(kEndEffectorStd, ee_std_, t.ee_std_);
  return t;
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
  if (!(lost_threshold_m > 0.0) || !std::isfinite(lost_threshold_m))
    fail("lost_threshold_m must be > 0");
  if (!(lost_after_s > 0.0) || !std::isfinite(lost_after_s)) fail("lost_after_s must be > 0");
}

std::optional<LostSpan> lost_span(const ErrorTrace& trace, const ScoringOptions& options) {
  const std::vector<double>&t = trace.time_s(), &e = trace.translation_m();
  // A stretch "lasts more than lost_after_s" within rounding of the times.
  const double longer_than = options.lost_after_s + kTimeMatch_s;
  std::optional<double> from;
  std::size_t first = 0;  // the stretch's first sample
  std::optional<LostSpan> span;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < options.converged_after_s) continue;
    const bool above = !(e[i] <= options.lost_threshold_m);  // NaN is above
    if (!above) {
      from.reset();
      continue;
    }
    if (!from) {
      from = t[i];
      first = i;
    }
    // The stretch goes on while the next sample is above too.
    const bool ends = i + 1 == t.size() || e[i + 1] <= options.lost_threshold_m;
    if (!ends || t[i] - *from <= longer_than) continue;
    const double duration_s = t[i] - *from;
    if (span) {  // a later stretch: counted
      ++span->stretches;
      span->total_s += duration_s;
      continue;
    }
    span = LostSpan{*from, duration_s};
    span->total_s = duration_s;
    if (trace.has_in_view() && trace.num_end_effectors() == 1) {
      std::size_t out = 0;
      for (std::size_t k = first; k <= i; ++k) out += !trace.end_effector_in_view(k, 0);
      span->out_of_view_share = double(out) / double(i - first + 1);
    }
  }
  return span;
}

std::string out_of_view_note(const LostSpan& span) {
  if (!(span.out_of_view_share > 0)) return "";  // none, or NaN: not known
  return "out of the camera's view for " +
         std::to_string(int(std::lround(100 * span.out_of_view_share))) + "% of it";
}

std::string more_stretches_note(const LostSpan& span) {
  if (span.stretches <= 1) return "";
  char total[32];
  std::snprintf(total, sizeof total, "%.1f", span.total_s);
  return std::to_string(span.stretches) + " stretches, " + total + " s in all";
}

std::string lost_span_notes(const LostSpan& span) {
  std::string notes = out_of_view_note(span);
  if (const std::string more = more_stretches_note(span); !more.empty())
    notes += (notes.empty() ? "" : "; ") + more;
  return notes;
}

void Coverage::add(double error, double std) {
  if (std == 0.0) return;  // not estimated
  ++estimated;
  within += std::abs(error) <= 2.0 * std;  // false for NaN
}

CameraOffset camera_offset_of(const Eigen::Isometry3d& T) {
  // R = Rx(a) Ry(b) Rz(c): R(0,2) = sin b, R(1,2) = -sin a cos b,
  // R(2,2) = cos a cos b, R(0,1) = -cos b sin c, R(0,0) = cos b cos c.
  const Eigen::Matrix3d& R = T.linear();
  CameraOffset o;
  o.head<3>() = T.translation();
  o[3] = std::atan2(-R(1, 2), R(2, 2));
  o[4] = std::asin(std::clamp(R(0, 2), -1.0, 1.0));
  o[5] = std::atan2(-R(0, 1), R(0, 0));
  return o;
}

CameraPoses::CameraPoses(std::shared_ptr<const RobotModel> model)
    : model_(std::move(model)), state_(*model_), q_(model_->num_joints()) {
  if (model_->camera_link() == model_->nominal_camera_link())
    fail("the robot model " + model_->source() + " has no virtual camera joints");
}

Eigen::Isometry3d CameraPoses::camera(const Eigen::VectorXd& angle_rad,
                                      const CameraOffset& offset) {
  q_.head(angle_rad.size()) = angle_rad;
  q_.tail<6>() = offset;
  forward_kinematics(*model_, q_, state_);
  return state_.T_root_link[model_->camera_link()];
}

CameraOffset CameraPoses::offset_to(const Eigen::VectorXd& angle_rad,
                                    const Eigen::Isometry3d& T_base_camera) {
  q_.head(angle_rad.size()) = angle_rad;
  q_.tail<6>().setZero();
  forward_kinematics(*model_, q_, state_);
  return camera_offset_of(state_.T_root_link[model_->nominal_camera_link()].inverse() *
                          T_base_camera);
}

MethodScores::MethodScores(std::string method, std::vector<std::string> joint_names,
                           std::vector<std::string> end_effectors)
    : method_(std::move(method)),
      joint_names_(std::move(joint_names)),
      end_effectors_(std::move(end_effectors)) {
  if (end_effectors_.empty()) fail("method '" + method_ + "': no end effector to score");
}

void MethodScores::begin_run() { runs_.emplace_back(joint_names_.size(), end_effectors_.size()); }

void MethodScores::add(const ScoredSample& sample) {
  if (runs_.empty()) begin_run();
  runs_.back().add(sample);
}

void MethodScores::add(double time_s, const PoseError& ee, std::span<const double> angle_error_rad,
                       std::span<const double> bias_error_rad) {
  if (runs_.empty()) begin_run();
  runs_.back().add(time_s, ee, angle_error_rad, bias_error_rad);
}

void MethodScores::add_run(ErrorTrace run) {
  if (run.num_joints() != joint_names_.size())
    fail("method '" + method_ + "': a run has " + std::to_string(run.num_joints()) +
         " joints, expected " + std::to_string(joint_names_.size()));
  if (run.num_end_effectors() != end_effectors_.size())
    fail("method '" + method_ + "': a run has " + std::to_string(run.num_end_effectors()) +
         " end effectors, expected " + std::to_string(end_effectors_.size()));
  runs_.push_back(std::move(run));
}

void MethodScores::merge(const MethodScores& other) {
  if (other.joint_names_ != joint_names_)
    fail("method '" + method_ + "': cannot pool runs with different joints");
  if (other.end_effectors_ != end_effectors_)
    fail("method '" + method_ + "': cannot pool runs with different end effectors");
  runs_.insert(runs_.end(), other.runs_.begin(), other.runs_.end());
}

std::size_t MethodSummary::lost_runs() const {
  std::size_t n = 0;
  for (std::size_t r = 0; r < num_runs; ++r) n += run_lost(r);
  return n;
}

bool MethodSummary::run_lost(std::size_t run) const {
  for (const EndEffectorSummary& e : end_effectors)
    if (run < e.lost.size() && e.lost[run]) return true;
  return false;
}

namespace {

// Statistics over the samples at time >= from_s of every run.
ErrorStats stats_from(const std::vector<ErrorTrace>& runs, std::size_t num_joints, double from_s,
                      const std::vector<ErrorTrace>* reference) {
  ErrorStats s;
  std::vector<double> trans, rot, cam_trans, cam_rot;
  std::vector<std::vector<double>> angle(num_joints), bias(num_joints);
  std::vector<Coverage> angle_cov(num_joints), bias_cov(num_joints);
  bool any_angle = false, any_bias = false, any_angle_cov = false, any_bias_cov = false;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const ErrorTrace& run = runs[r];
    const bool angle_cov_known = run.has_angle_errors() && run.has_angle_std();
    const bool bias_cov_known = run.has_bias_errors() && run.has_bias_std();
    const bool camera_cov_known = run.has_camera_offset_errors() && run.has_camera_offset_std();
    const bool ee_cov_known = run.has_end_effector_errors() && run.has_end_effector_std();
    for (std::size_t i = 0; i < run.size(); ++i) {
      if (run.time_s()[i] < from_s) continue;
      trans.push_back(run.translation_m()[i]);
      rot.push_back(run.rotation_rad()[i]);
      if (run.has_camera()) {
        cam_trans.push_back(run.camera_translation_m()[i]);
        cam_rot.push_back(run.camera_rotation_rad()[i]);
      }
      for (std::size_t j = 0; j < num_joints; ++j) {
        if (run.has_angle_errors()) angle[j].push_back(std::abs(run.angle_error_rad(i, j)));
        if (run.has_bias_errors()) bias[j].push_back(std::abs(run.bias_error_rad(i, j)));
        if (angle_cov_known) angle_cov[j].add(run.angle_error_rad(i, j), run.angle_std_rad(i, j));
        if (bias_cov_known) bias_cov[j].add(run.bias_error_rad(i, j), run.bias_std_rad(i, j));
      }
      if (camera_cov_known)
        for (std::size_t k = 0; k < 6; ++k)
          s.camera_axis_coverage[k].add(run.camera_offset_error(i, k), run.camera_offset_std(i, k));
      if (ee_cov_known)
        for (std::size_t e = 0; e < run.num_end_effectors(); ++e)
          for (std::size_t k = 0; k < 6; ++k)
            (k < 3 ? s.end_effector_position_coverage : s.end_effector_rotation_coverage)
                .add(run.end_effector_error(i, e, k), run.end_effector_std(i, e, k));
    }
    any_angle |= run.has_angle_errors();
    any_bias |= run.has_bias_errors();
    any_angle_cov |= angle_cov_known;
    any_bias_cov |= bias_cov_known;
    if (reference) {
      const ReferenceComparison c = compare_with_reference(run, (*reference)[r], from_s);
      s.reference.compared += c.compared;
      s.reference.worse += c.worse;
    }
  }
  s.translation_m = percentiles(trans);
  s.rotation_rad = percentiles(rot);
  s.camera_translation_m = percentiles(cam_trans);
  s.camera_rotation_rad = percentiles(cam_rot);
  if (any_angle)
    for (const auto& v : angle) s.joint_angle_abs_error_rad.push_back(percentiles(v));
  if (any_bias)
    for (const auto& v : bias) s.joint_bias_abs_error_rad.push_back(percentiles(v));
  if (any_angle_cov) s.joint_angle_coverage = angle_cov;
  if (any_bias_cov) s.joint_bias_coverage = bias_cov;
  for (const Coverage& c : angle_cov) s.angle_coverage += c;
  for (const Coverage& c : bias_cov) s.bias_coverage += c;
  for (const Coverage& c : s.camera_axis_coverage) s.camera_offset_coverage += c;
  return s;
}

}  // namespace

MethodSummary MethodScores::summary(const ScoringOptions& options,
                                    const MethodScores* reference) const {
  options.validate();
  if (reference && reference->runs_.size() != runs_.size())
    fail("method '" + method_ + "' has " + std::to_string(runs_.size()) + " runs but reference '" +
         reference->method_ + "' has " + std::to_string(reference->runs_.size()));
  if (reference && reference->end_effectors_ != end_effectors_)
    fail("method '" + method_ + "' and reference '" + reference->method_ +
         "' score different end effectors");
  const std::vector<ErrorTrace>* ref = reference ? &reference->runs_ : nullptr;
  const std::size_t nj = joint_names_.size();
  MethodSummary m;
  m.method = method_;
  m.joint_names = joint_names_;
  m.num_runs = runs_.size();
  m.all = stats_from(runs_, nj, -kInf, ref);
  m.converged = stats_from(runs_, nj, options.converged_after_s, ref);
  for (const ErrorTrace& run : runs_)
    m.time_to_converge_s.push_back(time_to_converge_s(run, options.convergence_threshold_m));
  for (std::size_t e = 0; e < end_effectors_.size(); ++e) {
    std::vector<ErrorTrace> runs, ref_runs;
    for (const ErrorTrace& run : runs_) runs.push_back(run.end_effector(e));
    if (ref)
      for (const ErrorTrace& run : *ref) ref_runs.push_back(run.end_effector(e));
    EndEffectorSummary es;
    es.name = end_effectors_[e];
    es.all = stats_from(runs, 0, -kInf, ref ? &ref_runs : nullptr);
    es.converged = stats_from(runs, 0, options.converged_after_s, ref ? &ref_runs : nullptr);
    for (const ErrorTrace& run : runs) {
      es.time_to_converge_s.push_back(time_to_converge_s(run, options.convergence_threshold_m));
      es.lost.push_back(lost_span(run, options));
    }
    m.end_effectors.push_back(std::move(es));
  }
  return m;
}

}  // namespace arttrack::sim
