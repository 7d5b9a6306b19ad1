#include "arttrack/tracker/internal/encoder_smoother.h"

#include <cmath>
#include <string>

#include "arttrack/tracker/error.h"

namespace arttrack {

EncoderSmoother::EncoderSmoother(std::span<const double> encoder_var_rad2,
                                 std::span<const char> smoothed,
                                 double rate_diffusion_rad_per_s_per_sqrt_s)
    : var_q_(encoder_var_rad2.begin(), encoder_var_rad2.end()),
      smoothed_(smoothed.begin(), smoothed.end()),
      rate_var_(rate_diffusion_rad_per_s_per_sqrt_s * rate_diffusion_rad_per_s_per_sqrt_s) {
  if (encoder_var_rad2.size() != smoothed.size())
    throw InputError("encoder smoother: " + std::to_string(encoder_var_rad2.size()) +
                     " encoder variances for " + std::to_string(smoothed.size()) + " joints");
  if (!(std::isfinite(rate_var_) && rate_var_ > 0))
    throw InputError("encoder smoother: the rate diffusion must be finite and positive, got " +
                     std::to_string(rate_diffusion_rad_per_s_per_sqrt_s));
  for (double v : var_q_)
    if (!(std::isfinite(v) && v > 0))
      throw InputError("encoder smoother: an encoder variance is not finite and positive: " +
                       std::to_string(v));
  const std::size_t n = var_q_.size();
  angle_.assign(n, 0.0);
  rate_.assign(n, 0.0);
  p_aa_.assign(n, 0.0);
  p_av_.assign(n, 0.0);
  p_vv_.assign(n, 0.0);
}

void EncoderSmoother::set_encoder_var(int j, double var_rad2) {
  if (j < 0 || j >= int(var_q_.size()) || !(std::isfinite(var_rad2) && var_rad2 > 0))
    throw InputError("encoder smoother: joint " + std::to_string(j) + " of " +
                     std::to_string(var_q_.size()) + " cannot take encoder variance " +
                     std::to_string(var_rad2));
  var_q_[std::size_t(j)] = var_rad2;
}

void EncoderSmoother::smooth(double dt_s, std::span<double> readings_rad) {
  if (readings_rad.size() != var_q_.size())
    throw InputError("encoder smoother: " + std::to_string(readings_rad.size()) +
                     " readings, expected " + std::to_string(var_q_.size()));
  if (started_ && !(std::isfinite(dt_s) && dt_s >= 0))
    throw InputError("encoder smoother: time step " + std::to_string(dt_s) +
                     " s is negative or not finite");
  const double dt = dt_s, dt2 = dt * dt;
  for (std::size_t j = 0; j < var_q_.size(); ++j) {
    if (!smoothed_[j]) continue;
    const double q = readings_rad[j];
    if (!started_) {
      angle_[j] = q;
      rate_[j] = 0;
      p_aa_[j] = var_q_[j];
      p_av_[j] = 0;
      p_vv_[j] = kInitialRateStdRadPerS * kInitialRateStdRadPerS;
      continue;
    }
    // Predict: F = [1 dt; 0 1], Q = sigma_v^2 [dt^3/3 dt^2/2; dt^2/2 dt].
    const double a = angle_[j] + rate_[j] * dt;
    const double aa = p_aa_[j] + 2 * dt * p_av_[j] + dt2 * p_vv_[j] + rate_var_ * dt2 * dt / 3;
    const double av = p_av_[j] + dt * p_vv_[j] + rate_var_ * dt2 / 2;
    const double vv = p_vv_[j] + rate_var_ * dt;
    // Update with the reading (H = [1 0]).
    const double s = aa + var_q_[j];
    const double k_a = aa / s, k_v = av / s, innovation = q - a;
    angle_[j] = a + k_a * innovation;
    rate_[j] += k_v * innovation;
    p_aa_[j] = (1 - k_a) * aa;
    p_av_[j] = (1 - k_a) * av;
    p_vv_[j] = vv - k_v * av;
    readings_rad[j] = angle_[j];
  }
  started_ = true;
}

}  // namespace arttrack
