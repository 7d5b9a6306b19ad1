// The mean's lag as uncertainty (uncertainty.mean_lag_scale; docs/accuracy.md,
// "The mean's lag as uncertainty"): the reported covariance's marginals
// widened while a state that should stand still is still moving.
//
// A bias and a camera offset are constant, or nearly, so once the images
// have placed them their estimates stand still. Under model error the first
// images place some of them on a wrong point of a ridge (arm7's shoulder and
// elbow biases and its camera's yaw), and the mean then slides back along it
// over 5-15 s under a standard deviation already small: the reported
// covariance knows what the images say, not where the mean still has to go.
// While a mean moves, the difference of a fast and a slow running average
// of it measures how far it went over the slow one's time: for a steady
// drift v it tends to v (T - T_fast), as the discrete averages below give
// it. Each tracked state's reported variance gains scale times that
// difference squared; a mean that stands still gains nothing, so the steady
// state keeps what the images say.
//
// The first kSettle_s after a state starts (the first image's acquisition)
// or restarts (a search re-opened it) are not counted: the particles
// collapse over the first images after a search and move the mean by what
// the search's broad prior already covered.
//
// Only the report widens: the filters, the refinement's prior and the next
// image's covariance do not see it, so the estimate is the same.
//
// Setup: which states are tracked, the scale and the slow time constant.
// Workspace: per state, the two averages and its start (sized at
// construction: allocation-free after it). Internal to the tracker
// (tracker/internal: not installed). Not thread-safe: the image thread's.
#pragma once

#include <limits>
#include <span>
#include <vector>

namespace arttrack {

class MeanLag {
 public:
  static constexpr double kFastTimeConstant_s = 0.2;
  static constexpr double kSettle_s = 0.5;

  // `tracked[i]`: whether state i's mean should stand still (a bias, a
  // camera offset); the others' variance stays 0. scale >= 0 (0: off);
  // time_constant_s > kFastTimeConstant_s.
  MeanLag(std::vector<char> tracked, double scale, double time_constant_s);

  // Every state's mean after an image at time_s (non-decreasing; a time
  // before the previous one counts as the same time).
  void update(double time_s, std::span<const double> means);
  // State i's mean was moved by a search: it starts again at the next update.
  void restart(int i);

  // Per state, the variance the mean's lag adds (0 untracked, settling, or off).
  std::span<const double> variance() const { return variance_; }
  int size() const { return int(tracked_.size()); }

 private:
  static constexpr double kNoTime = std::numeric_limits<double>::quiet_NaN();
  std::vector<char> tracked_;
  double scale_, time_constant_s_;
  double last_time_s_ = kNoTime;
  std::vector<double> start_s_;  // per state: when it (re)started; NaN: at the next update
  std::vector<double> fast_, slow_, variance_;
};

}  // namespace arttrack
