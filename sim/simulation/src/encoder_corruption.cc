#include "arttrack/sim/encoder_corruption.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "arttrack/tracker/error.h"
#include "validation_text.h"

namespace arttrack::sim {
namespace {

[[noreturn]] void fail_encoder_corruption(const std::string& what) {
  throw InputError("encoder corruption: " + what);
}

void require_nonnegative(double value, const char* field) {
  if (!(value >= 0.0) || !std::isfinite(value))
    fail_encoder_corruption(std::string(field) + " must be >= 0" + got(value));
}

}  // namespace

void EncoderGroupCorruption::validate() const {
  if (!std::isfinite(offset_rad))
    fail_encoder_corruption("offset_rad must be finite" + got(offset_rad));
  if (!std::isfinite(step_amplitude_rad))
    fail_encoder_corruption("step_amplitude_rad must be finite" + got(step_amplitude_rad));
  if (!(step_period_s > 0.0) || !std::isfinite(step_period_s))
    fail_encoder_corruption("step_period_s must be > 0" + got(step_period_s));
  if (!(step_ramp_time_s >= 0.0) || !(step_ramp_time_s <= 0.5 * step_period_s))
    fail_encoder_corruption("step_ramp_time_s must be in [0, step_period_s / 2]" +
                            got(step_ramp_time_s));
  require_nonnegative(compliance_rad_per_Nm, "compliance_rad_per_Nm");
  require_nonnegative(stretch_time_constant_s, "stretch_time_constant_s");
  require_nonnegative(noise_sigma_rad, "noise_sigma_rad");
  require_nonnegative(resolution_rad, "resolution_rad");
}

void EncoderCorruptionParams::validate() const {
  for (const EncoderGroupCorruption& g : groups) g.validate();
}

double alternating_step_rad(double t_s, double amplitude_rad, double period_s, double ramp_time_s) {
  // Half period h: +A, ramp down, then -A, ramp up; n counts half periods.
  const double h = 0.5 * period_s;
  const double n = std::floor(t_s / h);
  const double tau = t_s - n * h;
  const double sign = std::fmod(n, 2.0) == 0.0 ? 1.0 : -1.0;
  const double hold = h - ramp_time_s;
  if (tau < hold || ramp_time_s <= 0.0) return sign * amplitude_rad;
  // Cosine ramp from +sign A to -sign A: C1, zero slope at both ends.
  return sign * amplitude_rad * std::cos(std::numbers::pi * (tau - hold) / ramp_time_s);
}

EncoderCorruption::EncoderCorruption(std::vector<std::string> joint_names,
                                     const EncoderCorruptionParams& params, std::uint64_t seed)
    : joint_names_(std::move(joint_names)),
      joints_(joint_names_.size()),
      stretch_rad_(joint_names_.size(), 0.0),
      bias_rad_(joint_names_.size(), 0.0),
      rng_(seed) {
  params.validate();
  const std::size_t n = joint_names_.size();
  std::vector<bool> has_step(n), has_stretch(n), has_quantisation(n);
  std::vector<double> noise_var(n, 0.0);
  for (std::size_t gi = 0; gi < params.groups.size(); ++gi) {
    const EncoderGroupCorruption& g = params.groups[gi];
    std::vector<std::size_t> idx;
    if (g.joints.empty()) {
      for (std::size_t j = 0; j < n; ++j) idx.push_back(j);
    }
    for (const std::string& name : g.joints) {
      const auto it = std::find(joint_names_.begin(), joint_names_.end(), name);
      if (it == joint_names_.end())
        fail_encoder_corruption("group " + std::to_string(gi) + ": unknown joint '" + name + "'");
      idx.push_back(std::size_t(it - joint_names_.begin()));
    }
    for (std::size_t j : idx) {
      JointCorruption& c = joints_[j];
      auto claim = [&](std::vector<bool>& taken, const char* what) {
        if (taken[j])
          fail_encoder_corruption("group " + std::to_string(gi) + ": joint '" + joint_names_[j] +
                                  "' already has a " + what + " from another group");
        taken[j] = true;
      };
      c.offset_rad += g.offset_rad;
      noise_var[j] += g.noise_sigma_rad * g.noise_sigma_rad;
      if (g.step_amplitude_rad != 0.0) {
        claim(has_step, "step (step_amplitude_rad)");
        c.step_amplitude_rad = g.step_amplitude_rad;
        c.step_period_s = g.step_period_s;
        c.step_ramp_time_s = g.step_ramp_time_s;
      }
      if (g.compliance_rad_per_Nm != 0.0) {
        claim(has_stretch, "cable stretch (compliance_rad_per_Nm)");
        c.compliance_rad_per_Nm = g.compliance_rad_per_Nm;
        c.stretch_time_constant_s = g.stretch_time_constant_s;
      }
      if (g.resolution_rad != 0.0) {
        claim(has_quantisation, "quantisation (resolution_rad)");
        c.resolution_rad = g.resolution_rad;
      }
    }
  }
  for (std::size_t j = 0; j < n; ++j) joints_[j].noise_sigma_rad = std::sqrt(noise_var[j]);
}

void EncoderCorruption::corrupt(double t_s, double dt_s, std::span<const double> true_angles,
                                std::span<const double> load_torques_Nm,
                                std::span<double> readings_out) {
  const std::size_t n = joints_.size();
  if (true_angles.size() != n || readings_out.size() != n ||
      !(load_torques_Nm.empty() || load_torques_Nm.size() == n))
    throw std::invalid_argument("EncoderCorruption::corrupt: span sizes != number of joints");
  if (!std::isfinite(t_s) || t_s < last_t_s_) {
    std::ostringstream msg;
    msg << "encoder corruption: time stamps must not decrease (" << t_s << " after " << last_t_s_
        << ")";
    throw InputError(msg.str());
  }
  if (!(dt_s >= 0.0) || !std::isfinite(dt_s))
    fail_encoder_corruption("dt_s must be >= 0" + got(dt_s));
  last_t_s_ = t_s;
  for (std::size_t j = 0; j < n; ++j) {
    const JointCorruption& c = joints_[j];
    double bias = c.offset_rad;
    if (c.step_amplitude_rad != 0.0)
      bias += alternating_step_rad(t_s, c.step_amplitude_rad, c.step_period_s, c.step_ramp_time_s);
    if (c.compliance_rad_per_Nm != 0.0) {
      const double torque = load_torques_Nm.empty() ? 0.0 : load_torques_Nm[j];
      const double target = c.compliance_rad_per_Nm * torque;
      // Exact zero-order-hold step of tau db/dt = target - b.
      const double keep =
          c.stretch_time_constant_s > 0.0 ? std::exp(-dt_s / c.stretch_time_constant_s) : 0.0;
      stretch_rad_[j] = target + (stretch_rad_[j] - target) * keep;
      bias += stretch_rad_[j];
    }
    bias_rad_[j] = bias;
    double reading = true_angles[j] + bias;
    if (c.noise_sigma_rad > 0.0) reading += c.noise_sigma_rad * normal_(rng_);
    if (c.resolution_rad > 0.0) reading = c.resolution_rad * std::round(reading / c.resolution_rad);
    readings_out[j] = reading;
  }
}

}  // namespace arttrack::sim
