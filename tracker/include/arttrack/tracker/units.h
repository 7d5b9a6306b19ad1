// Angle units. Code works in radians; degrees appear only at the edges
// (YAML `_deg` keys, messages, pages), converted with one constant for each
// direction.
#pragma once

#include <numbers>

namespace arttrack {

// One degree in radians: radians = degrees * kRadPerDeg.
inline constexpr double kRadPerDeg = std::numbers::pi / 180;

// One radian in degrees: degrees = radians * kDegPerRad.
inline constexpr double kDegPerRad = 180 / std::numbers::pi;

}  // namespace arttrack
