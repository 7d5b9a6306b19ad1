// Range checks of configuration fields, in one wording for every key of the
// tracker's configuration: TrackerConfig::validate and the validate functions
// of the structs in it (DepthModelParams, JointFilterParams,
// CoordinateParticleFilterParams) hold the ranges, and this says how a value
// outside one is reported.
#pragma once

#include <string>
#include <string_view>

#include "arttrack/tracker/units.h"

namespace arttrack {

// The values a field may take, in the user's units (degrees for a `_deg`
// key): an interval, each end closed (the bound allowed) or open.
struct ConfigRange {
  double lo = 0;
  double hi = 0;
  bool lo_open = false;
  bool hi_open = false;
  // The key the lower bound comes from, when another field sets it.
  std::string lo_key;

  static ConfigRange closed(double lo, double hi) { return ends(lo, hi, false, false); }
  static ConfigRange open_closed(double lo, double hi) { return ends(lo, hi, true, false); }
  static ConfigRange open(double lo, double hi) { return ends(lo, hi, true, true); }
  static ConfigRange ends(double lo, double hi, bool lo_open, bool hi_open);

  bool contains(double value) const;
  // As the message shows it: "[0.1, 100]", "(0, 1)",
  // "[0.003 (depth_model.noise_std_m), 0.5]".
  std::string text() const;
};

// Throws ConfigKeyError(source, key, "= V is out of range R") unless the
// field's `value` lies in `range`. `unit` is one user unit in the field's
// units (kRadPerDeg for a `_deg` key whose field holds radians): the bounds are
// scaled by it, so that a value read at a bound (and scaled by the same
// factor) is inside, and the message shows the value in the user's units.
void check_range(std::string_view source, const std::string& key, double value,
                 const ConfigRange& range, double unit = 1.0);

// Throws ConfigKeyError(source, key, problem): a rule other than a range.
[[noreturn]] void fail_key(std::string_view source, const std::string& key,
                           const std::string& problem);

}  // namespace arttrack
