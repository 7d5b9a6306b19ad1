// The one colour map of every picture the simulator draws (depth frames in
// the run report, `render`'s depth previews, the sweep's heat maps): Turbo
// (A. Mikhailov, Google, 2019), a rainbow map made perceptually smoother
// than jet, from dark blue (0) through blue, cyan, green, yellow and orange
// to dark red (1). Internal to the testbed.
#pragma once

#include <cstdint>
#include <string>

namespace arttrack::sim {

// An 8-bit sRGB colour.
struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

// Turbo at t, clamped into [0, 1] (NaN: 0). Linear between 18 samples of
// the published 256-entry table (its entries 0, 15, 30, ..., 255), within
// 6/255 of every entry. turbo(0) = (48, 18, 59), turbo(1) = (122, 4, 3).
Rgb turbo(double t);

// "#rrggbb", lower case.
std::string hex(Rgb c);

// Relative luminance in [0, 1] (WCAG 2: sRGB decoded to linear light,
// 0.2126 R + 0.7152 G + 0.0722 B): text on a colour above 0.18 reads best
// black, below it white.
double relative_luminance(Rgb c);

}  // namespace arttrack::sim
