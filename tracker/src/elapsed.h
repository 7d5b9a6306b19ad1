// Wall time since an instant of the steady clock, in milliseconds: the
// tracker's timings (TrackerStats, TrackingHealth::last_acquisition_ms).
// Internal to the tracker (not installed).
#pragma once

#include <chrono>

namespace arttrack {

inline double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace arttrack
