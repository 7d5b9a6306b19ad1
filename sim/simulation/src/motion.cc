#include "arttrack/sim/motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <unordered_set>

#include "arttrack/tracker/error.h"
#include "validation_text.h"

namespace arttrack::sim {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

[[noreturn]] void fail(std::string_view part, std::string_view what) {
  std::ostringstream msg;
  msg << "motion " << part << ": " << what;
  throw InputError(msg.str());
}

void require_joints(std::string_view part, const std::vector<std::string>& joints) {
  if (joints.empty()) fail(part, "joints must list at least one joint");
}

// Minimum-jerk blend s(x) = 10 x^3 - 15 x^4 + 6 x^5 on [0, 1] and its
// derivative 30 x^2 (1 - x)^2: C2, with s' = s'' = 0 at both ends.
double min_jerk(double x) { return x * x * x * (10.0 + x * (-15.0 + 6.0 * x)); }
double min_jerk_rate(double x) { return 30.0 * x * x * (1.0 - x) * (1.0 - x); }

// Fade-in envelope e(t) rising from 0 at t = 0 to 1 at t = fade_s, and de/dt.
void fade_in(double t_s, double fade_s, double& e, double& de) {
  if (fade_s <= 0.0 || t_s >= fade_s) {
    e = 1.0, de = 0.0;
  } else if (t_s <= 0.0) {
    e = 0.0, de = 0.0;
  } else {
    const double x = t_s / fade_s;
    e = min_jerk(x), de = min_jerk_rate(x) / fade_s;
  }
}

}  // namespace

void SinusoidMotion::validate() const {
  require_joints("sinusoid", joints);
  if (!std::isfinite(amplitude_rad))
    fail("sinusoid", "amplitude_rad must be finite" + got(amplitude_rad));
  if (!(frequency_hz > 0.0) || !std::isfinite(frequency_hz))
    fail("sinusoid", "frequency_hz must be > 0" + got(frequency_hz));
  if (!std::isfinite(phase_rad)) fail("sinusoid", "phase_rad must be finite" + got(phase_rad));
  if (!centre_rad.empty() && centre_rad.size() != joints.size())
    fail("sinusoid", "centre_rad must be empty or have one value per joint");
  for (double c : centre_rad)
    if (!std::isfinite(c)) fail("sinusoid", "centre_rad must be finite" + got(c));
  if (!(fade_in_s >= 0.0) || !std::isfinite(fade_in_s))
    fail("sinusoid", "fade_in_s must be >= 0" + got(fade_in_s));
}

void WaypointMotion::validate() const {
  require_joints("waypoints", joints);
  if (times_s.empty()) fail("waypoints", "times_s must list at least one waypoint");
  if (positions_rad.size() != times_s.size())
    fail("waypoints", "positions_rad must have one entry per time in times_s");
  for (std::size_t i = 0; i < times_s.size(); ++i) {
    if (!(times_s[i] >= 0.0) || !std::isfinite(times_s[i]))
      fail("waypoints", "times_s[" + std::to_string(i) + "] must be >= 0" + got(times_s[i]));
    if (i > 0 && !(times_s[i] > times_s[i - 1]))
      fail("waypoints", "times_s must be strictly increasing (times_s[" + std::to_string(i) + "]" +
                            got(times_s[i]) + ")");
    if (positions_rad[i].size() != joints.size())
      fail("waypoints", "positions_rad[" + std::to_string(i) + "] must have one value per joint");
    for (double q : positions_rad[i])
      if (!std::isfinite(q))
        fail("waypoints", "positions_rad[" + std::to_string(i) + "] must be finite" + got(q));
  }
}

void RandomMotion::validate() const {
  require_joints("random", joints);
  if (!(amplitude_rad > 0.0) || !std::isfinite(amplitude_rad))
    fail("random", "amplitude_rad must be > 0" + got(amplitude_rad));
  if (!(speed_scale > 0.0) || !std::isfinite(speed_scale))
    fail("random", "speed_scale must be > 0" + got(speed_scale));
  if (!(base_speed_rad_per_s > 0.0) || !std::isfinite(base_speed_rad_per_s))
    fail("random", "base_speed_rad_per_s must be > 0" + got(base_speed_rad_per_s));
  if (!(margin_rad >= 0.0) || !std::isfinite(margin_rad))
    fail("random", "margin_rad must be >= 0" + got(margin_rad));
  if (num_components < 1) fail("random", "num_components must be >= 1" + got(num_components));
  if (!(fade_in_s >= 0.0) || !std::isfinite(fade_in_s))
    fail("random", "fade_in_s must be >= 0" + got(fade_in_s));
}

void OutOfViewMotion::validate() const {
  require_joints("out_of_view", joints);
  if (out_of_view_rad.size() != joints.size())
    fail("out_of_view", "out_of_view_rad must have one value per joint");
  for (double q : out_of_view_rad)
    if (!std::isfinite(q)) fail("out_of_view", "out_of_view_rad must be finite" + got(q));
  if (!(leave_s >= 0.0) || !std::isfinite(leave_s))
    fail("out_of_view", "leave_s must be >= 0" + got(leave_s));
  if (!(move_duration_s > 0.0) || !std::isfinite(move_duration_s))
    fail("out_of_view", "move_duration_s must be > 0" + got(move_duration_s));
  if (!(return_s >= leave_s + move_duration_s) || !std::isfinite(return_s))
    fail("out_of_view", "return_s must be >= leave_s + move_duration_s" + got(return_s));
}

JointTrajectory::JointTrajectory(std::vector<std::string> joint_names, std::vector<double> home_rad,
                                 std::vector<JointLimit> limits)
    : joint_names_(std::move(joint_names)),
      home_rad_(std::move(home_rad)),
      limits_(std::move(limits)),
      terms_(joint_names_.size()) {
  if (home_rad_.size() != joint_names_.size())
    fail("trajectory", "home configuration must have one value per joint");
  if (limits_.size() != joint_names_.size())
    fail("trajectory", "limits must have one entry per joint");
  std::unordered_set<std::string_view> seen;
  for (std::size_t j = 0; j < joint_names_.size(); ++j) {
    const std::string& name = joint_names_[j];
    if (!seen.insert(name).second) fail("trajectory", "joint '" + name + "' listed twice");
    const JointLimit& lim = limits_[j];
    if (std::isnan(lim.lower_rad) || std::isnan(lim.upper_rad) || lim.lower_rad > lim.upper_rad)
      fail("trajectory", "joint '" + name + "' has lower limit above upper limit");
    if (!std::isfinite(home_rad_[j]) || home_rad_[j] < lim.lower_rad ||
        home_rad_[j] > lim.upper_rad)
      fail("trajectory",
           "home angle of joint '" + name + "' is outside its limits" + got(home_rad_[j]));
  }
}

std::size_t JointTrajectory::joint_index(std::string_view name) const {
  for (std::size_t j = 0; j < joint_names_.size(); ++j)
    if (joint_names_[j] == name) return j;
  fail("trajectory", "unknown joint " + quote_value(name));
}

std::vector<std::size_t> JointTrajectory::resolve(const std::vector<std::string>& joints,
                                                  std::string_view part) const {
  std::vector<std::size_t> idx;
  for (const std::string& name : joints) {
    const auto it = std::find(joint_names_.begin(), joint_names_.end(), name);
    if (it == joint_names_.end()) fail(part, "unknown joint " + quote_value(name));
    const std::size_t j = std::size_t(it - joint_names_.begin());
    if (std::find(idx.begin(), idx.end(), j) != idx.end())
      fail(part, "joint '" + name + "' listed twice");
    idx.push_back(j);
  }
  return idx;
}

void JointTrajectory::add(const SinusoidMotion& part) {
  part.validate();
  const std::vector<std::size_t> idx = resolve(part.joints, "sinusoid");
  for (std::size_t i = 0; i < idx.size(); ++i) {
    const std::size_t j = idx[i];
    const double centre = part.centre_rad.empty() ? home_rad_[j] : part.centre_rad[i];
    terms_[j].sines.push_back({centre - home_rad_[j], part.amplitude_rad,
                               kTwoPi * part.frequency_hz, part.phase_rad, part.fade_in_s});
  }
}

void JointTrajectory::add(const WaypointMotion& part) {
  part.validate();
  const std::vector<std::size_t> idx = resolve(part.joints, "waypoints");
  for (std::size_t i = 0; i < idx.size(); ++i) {
    const std::size_t j = idx[i];
    WaypointTerm term;
    term.times_s = part.times_s;
    for (std::size_t k = 0; k < part.times_s.size(); ++k) {
      const double q = part.positions_rad[k][i];
      if (q < limits_[j].lower_rad || q > limits_[j].upper_rad)
        fail("waypoints", "positions_rad[" + std::to_string(k) + "] of joint '" + joint_names_[j] +
                              "' is outside its limits" + got(q));
      term.values_rad.push_back(q);
    }
    terms_[j].waypoints.push_back(std::move(term));
  }
}

void JointTrajectory::add(const RandomMotion& part, std::mt19937_64& rng) {
  part.validate();
  const std::vector<std::size_t> idx = resolve(part.joints, "random");
  std::uniform_real_distribution<double> ratio(0.5, 1.5), phase(0.0, kTwoPi);
  const int K = part.num_components;
  const double target_rms_speed = part.speed_scale * part.base_speed_rad_per_s;
  for (std::size_t j : idx) {
    const JointLimit& lim = limits_[j];
    // Room for the motion: the limits minus the margin; the amplitude shrinks
    // if the room is narrower than 2 A, and the centre moves off home so that
    // centre +- A stays inside.
    const double lo = lim.lower_rad + part.margin_rad, hi = lim.upper_rad - part.margin_rad;
    double amplitude = 0.0, centre = 0.5 * (lim.lower_rad + lim.upper_rad);
    if (hi >= lo) {
      amplitude = std::min(part.amplitude_rad, 0.5 * (hi - lo));
      // With the room exactly 2 A, lo + A can round above hi - A: std::clamp
      // with its bounds the wrong way round is undefined.
      const double lowest = lo + amplitude, highest = std::max(lowest, hi - amplitude);
      centre = std::clamp(home_rad_[j], lowest, highest);
    }
    RandomTerm term{centre - home_rad_[j], part.fade_in_s, {}, {}, {}};
    std::vector<double> nu(K);
    double sum_nu2 = 0.0;
    for (int k = 0; k < K; ++k) sum_nu2 += (nu[k] = ratio(rng)) * nu[k];
    // Equal weights A/K bound the sum by A. Its RMS speed at the nominal
    // amplitude is (A/K) 2 pi lambda sqrt(sum nu_k^2 / 2); lambda (Hz) sets it
    // to the target.
    const double lambda =
        target_rms_speed * K / (part.amplitude_rad * kTwoPi * std::sqrt(0.5 * sum_nu2));
    for (int k = 0; k < K; ++k) {
      term.weight_rad.push_back(amplitude / K);
      term.omega_rad_per_s.push_back(kTwoPi * lambda * nu[k]);
      term.phase_rad.push_back(phase(rng));
    }
    terms_[j].randoms.push_back(std::move(term));
  }
}

void JointTrajectory::add(const OutOfViewMotion& part) {
  part.validate();
  const std::vector<std::size_t> idx = resolve(part.joints, "out_of_view");
  WaypointMotion wp;
  wp.joints = part.joints;
  wp.times_s = {part.leave_s, part.leave_s + part.move_duration_s, part.return_s,
                part.return_s + part.move_duration_s};
  std::vector<double> home;
  for (std::size_t j : idx) home.push_back(home_rad_[j]);
  wp.positions_rad = {home, part.out_of_view_rad, part.out_of_view_rad, home};
  // No stay out of view: the two middle waypoints would share a time.
  if (part.return_s == part.leave_s + part.move_duration_s) {
    wp.times_s.erase(wp.times_s.begin() + 2);
    wp.positions_rad.erase(wp.positions_rad.begin() + 2);
  }
  add(wp);
}

void JointTrajectory::evaluate(std::size_t j, double t_s, double& q, double& qd) const {
  const double home = home_rad_[j];
  q = home, qd = 0.0;
  const JointTerms& terms = terms_[j];
  double e, de;
  for (const SineTerm& s : terms.sines) {
    fade_in(t_s, s.fade_in_s, e, de);
    const double arg = s.omega_rad_per_s * t_s + s.phase_rad;
    const double d = s.offset_rad + s.amplitude_rad * std::sin(arg);
    q += e * d;
    qd += de * d + e * s.amplitude_rad * s.omega_rad_per_s * std::cos(arg);
  }
  for (const WaypointTerm& w : terms.waypoints) {
    const std::vector<double>& ts = w.times_s;
    const std::vector<double>& vs = w.values_rad;
    if (t_s <= ts.front()) {
      q += vs.front() - home;
    } else if (t_s >= ts.back()) {
      q += vs.back() - home;
    } else {
      // Segment [t_i, t_{i+1}) containing t_s.
      const std::size_t i =
          std::size_t(std::upper_bound(ts.begin(), ts.end(), t_s) - ts.begin()) - 1;
      const double dt = ts[i + 1] - ts[i], x = (t_s - ts[i]) / dt, dv = vs[i + 1] - vs[i];
      q += vs[i] + dv * min_jerk(x) - home;
      qd += dv * min_jerk_rate(x) / dt;
    }
  }
  for (const RandomTerm& r : terms.randoms) {
    fade_in(t_s, r.fade_in_s, e, de);
    double d = r.offset_rad, dd = 0.0;
    for (std::size_t k = 0; k < r.weight_rad.size(); ++k) {
      const double arg = r.omega_rad_per_s[k] * t_s + r.phase_rad[k];
      d += r.weight_rad[k] * std::sin(arg);
      dd += r.weight_rad[k] * r.omega_rad_per_s[k] * std::cos(arg);
    }
    q += e * d;
    qd += de * d + e * dd;
  }
  const JointLimit& lim = limits_[j];
  if (q < lim.lower_rad) {
    q = lim.lower_rad, qd = 0.0;
  } else if (q > lim.upper_rad) {
    q = lim.upper_rad, qd = 0.0;
  }
}

void JointTrajectory::position(double t_s, std::span<double> q_out) const {
  if (q_out.size() != num_joints())
    throw std::invalid_argument("JointTrajectory::position: output size != number of joints");
  double qd;
  for (std::size_t j = 0; j < num_joints(); ++j) evaluate(j, t_s, q_out[j], qd);
}

void JointTrajectory::velocity(double t_s, std::span<double> qd_out) const {
  if (qd_out.size() != num_joints())
    throw std::invalid_argument("JointTrajectory::velocity: output size != number of joints");
  double q;
  for (std::size_t j = 0; j < num_joints(); ++j) evaluate(j, t_s, q, qd_out[j]);
}

std::vector<double> JointTrajectory::position(double t_s) const {
  std::vector<double> q(num_joints());
  position(t_s, q);
  return q;
}

std::vector<double> JointTrajectory::velocity(double t_s) const {
  std::vector<double> qd(num_joints());
  velocity(t_s, qd);
  return qd;
}

}  // namespace arttrack::sim
