#include "arttrack/tracker/internal/mean_lag.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "arttrack/tracker/error.h"

namespace arttrack {

MeanLag::MeanLag(std::vector<char> tracked, double scale, double time_constant_s)
    : tracked_(std::move(tracked)),
      scale_(scale),
      time_constant_s_(time_constant_s),
      start_s_(tracked_.size(), kNoTime),
      fast_(tracked_.size(), 0.0),
      slow_(tracked_.size(), 0.0),
      variance_(tracked_.size(), 0.0) {
  if (!(scale >= 0) || !std::isfinite(scale))
    throw InputError("mean lag: scale must be finite and at least 0, not " + std::to_string(scale));
  if (!(time_constant_s > kFastTimeConstant_s) || !std::isfinite(time_constant_s))
    throw InputError("mean lag: time constant must be finite and over " +
                     std::to_string(kFastTimeConstant_s) + " s, not " +
                     std::to_string(time_constant_s));
}

void MeanLag::update(double time_s, std::span<const double> means) {
  ARTTRACK_CHECK_ARGUMENT(means.size() == tracked_.size());
  if (scale_ == 0) return;
  const double dt = std::isnan(last_time_s_) ? 0.0 : std::max(0.0, time_s - last_time_s_);
  last_time_s_ = std::isnan(last_time_s_) ? time_s : std::max(last_time_s_, time_s);
  // Each average moves the share 1 - exp(-dt / tau) of the way to the mean.
  const double fast_share = -std::expm1(-dt / kFastTimeConstant_s);
  const double slow_share = -std::expm1(-dt / time_constant_s_);
  for (std::size_t i = 0; i < tracked_.size(); ++i) {
    if (!tracked_[i]) continue;
    if (std::isnan(start_s_[i])) start_s_[i] = last_time_s_;
    const double mean = means[i];
    if (!std::isfinite(mean) || last_time_s_ - start_s_[i] < kSettle_s) {
      // Settling (or no mean to follow): both averages wait at the mean.
      fast_[i] = slow_[i] = std::isfinite(mean) ? mean : 0.0;
      variance_[i] = 0;
      continue;
    }
    fast_[i] += fast_share * (mean - fast_[i]);
    slow_[i] += slow_share * (mean - slow_[i]);
    const double lag = fast_[i] - slow_[i];
    variance_[i] = scale_ * lag * lag;
  }
}

void MeanLag::restart(int i) {
  ARTTRACK_CHECK_ARGUMENT(i >= 0 && i < size());
  start_s_[std::size_t(i)] = kNoTime;
  variance_[std::size_t(i)] = 0;
}

}  // namespace arttrack
