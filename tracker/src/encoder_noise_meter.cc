#include "arttrack/tracker/internal/encoder_noise_meter.h"

#include <cmath>
#include <numbers>
#include <string>

#include "arttrack/tracker/error.h"

namespace arttrack {

EncoderNoiseMeter::EncoderNoiseMeter(std::span<const char> measured, double time_constant_s)
    : measured_(measured.begin(), measured.end()),
      time_constant_s_(time_constant_s),
      mean_abs_(measured.size(), 0.0) {
  if (!(time_constant_s > 0) || !std::isfinite(time_constant_s))
    throw InputError("encoder noise meter: time constant must be finite and positive");
  for (std::vector<double>& q : q_) q.assign(measured.size(), 0.0);
}

void EncoderNoiseMeter::add(double time_s, std::span<const double> readings) {
  if (readings.size() != measured_.size())
    throw InputError("encoder noise meter: " + std::to_string(readings.size()) +
                     " readings, expected " + std::to_string(measured_.size()));
  if (readings_ > 0 && !(time_s > t_s_[2])) return;
  if (readings_ >= 3) {
    // The divided difference's weights over (t0, t1, t2, time_s), as a unit
    // vector: d / |w| directly.
    const double t[4] = {t_s_[0], t_s_[1], t_s_[2], time_s};
    double w[4], norm2 = 0;
    for (int i = 0; i < 4; ++i) {
      double product = 1;
      for (int j = 0; j < 4; ++j)
        if (j != i) product *= t[i] - t[j];
      w[i] = 1 / product;
      norm2 += w[i] * w[i];
    }
    const double inv_norm = 1 / std::sqrt(norm2);
    for (double& wi : w) wi *= inv_norm;
    const double keep = std::exp(-(time_s - t_s_[2]) / time_constant_s_);
    weight_ = keep * weight_ + (1 - keep);
    for (std::size_t j = 0; j < measured_.size(); ++j) {
      if (!measured_[j]) continue;
      // The weights sum to 0: differences from the newest reading keep the
      // sum's precision whatever the angle.
      const double q = readings[j];
      const double d = w[0] * (q_[0][j] - q) + w[1] * (q_[1][j] - q) + w[2] * (q_[2][j] - q);
      mean_abs_[j] = keep * mean_abs_[j] + (1 - keep) * std::abs(d);
    }
  }
  for (std::size_t j = 0; j < measured_.size(); ++j)
    q_[0][j] = q_[1][j], q_[1][j] = q_[2][j], q_[2][j] = readings[j];
  t_s_[0] = t_s_[1], t_s_[1] = t_s_[2], t_s_[2] = time_s;
  ++readings_;
}

double EncoderNoiseMeter::noise_std(int j) const {
  if (j < 0 || j >= num_joints() || !measured_[std::size_t(j)] || differences() < kMinDifferences ||
      !(weight_ > 0))
    return std::numeric_limits<double>::quiet_NaN();
  return mean_abs_[std::size_t(j)] / weight_ * std::sqrt(std::numbers::pi / 2);
}

}  // namespace arttrack
