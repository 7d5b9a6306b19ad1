#include "arttrack/tracker/internal/encoder_noise_meter.h"

#include <cmath>
#include <numbers>

#include "arttrack/tracker/error.h"

namespace arttrack {

EncoderNoiseMeter::EncoderNoiseMeter(std::span<const char> measured, double time_constant_s)
    : measured_(measured.begin(), measured.end()),
      time_constant_s_(time_constant_s),
      q0_(measured.size(), 0.0),
      q1_(measured.size(), 0.0),
      mean_abs_(measured.size(), 0.0) {
  if (!(time_constant_s > 0) || !std::isfinite(time_constant_s))
    throw InputError("encoder noise meter: time constant must be finite and positive");
}

void EncoderNoiseMeter::add(double time_s, std::span<const double> readings) {
  if (readings.size() != measured_.size())
    throw InputError("encoder noise meter: " + std::to_string(readings.size()) +
                     " readings, expected " + std::to_string(measured_.size()));
  if (readings_ > 0 && !(time_s > t1_s_)) return;
  if (readings_ >= 2) {
    const double dt1 = t1_s_ - t0_s_, dt2 = time_s - t1_s_;
    const double r = dt2 / dt1;
    const double factor_sqrt = std::sqrt(1 + (1 + r) * (1 + r) + r * r);
    // Weighted by the time since the previous reading, so the average is
    // over time_constant_s whatever the encoders' rate.
    const double keep = std::exp(-dt2 / time_constant_s_);
    weight_ = keep * weight_ + (1 - keep);
    for (std::size_t j = 0; j < measured_.size(); ++j) {
      if (!measured_[j]) continue;
      const double d = readings[j] - q1_[j] - r * (q1_[j] - q0_[j]);
      mean_abs_[j] = keep * mean_abs_[j] + (1 - keep) * std::abs(d) / factor_sqrt;
    }
  }
  for (std::size_t j = 0; j < measured_.size(); ++j) q0_[j] = q1_[j], q1_[j] = readings[j];
  t0_s_ = t1_s_;
  t1_s_ = time_s;
  ++readings_;
}

double EncoderNoiseMeter::noise_std(int j) const {
  if (j < 0 || j >= num_joints() || !measured_[std::size_t(j)] || readings_ - 2 < kMinReadings ||
      !(weight_ > 0))
    return std::numeric_limits<double>::quiet_NaN();
  return mean_abs_[std::size_t(j)] / weight_ * std::sqrt(std::numbers::pi / 2);
}

}  // namespace arttrack
