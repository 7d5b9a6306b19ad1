#include "arttrack/sim/internal/colour_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace arttrack::sim {

namespace {

// Every 15th entry of the published Turbo table (sRGB in [0, 1]).
constexpr int kSamples = 18;
constexpr double kTurbo[kSamples][3] = {
    {0.18995, 0.07176, 0.23217}, {0.24830, 0.24143, 0.61286}, {0.27509, 0.40072, 0.86692},
    {0.26878, 0.54995, 0.99303}, {0.18625, 0.69775, 0.95498}, {0.10026, 0.82955, 0.81389},
    {0.13526, 0.92197, 0.66556}, {0.32006, 0.97974, 0.47654}, {0.54658, 0.99907, 0.29581},
    {0.71577, 0.96875, 0.20815}, {0.85868, 0.88655, 0.21230}, {0.96049, 0.77181, 0.22811},
    {0.99654, 0.63193, 0.18738}, {0.97545, 0.45740, 0.11305}, {0.91024, 0.29599, 0.04814},
    {0.80799, 0.17753, 0.01660}, {0.66449, 0.08436, 0.00424}, {0.47960, 0.01583, 0.01055}};

std::uint8_t byte(double v) { return std::uint8_t(std::lround(255 * std::clamp(v, 0.0, 1.0))); }

double linear(std::uint8_t v) {
  const double c = v / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

}  // namespace

Rgb turbo(double t) {
  if (std::isnan(t)) t = 0;
  const double x = std::clamp(t, 0.0, 1.0) * (kSamples - 1);
  const int i = std::min(kSamples - 2, int(x));
  const double f = x - i;
  const auto channel = [&](int c) { return kTurbo[i][c] + f * (kTurbo[i + 1][c] - kTurbo[i][c]); };
  return {byte(channel(0)), byte(channel(1)), byte(channel(2))};
}

std::string hex(Rgb c) {
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

double relative_luminance(Rgb c) {
  return 0.2126 * linear(c.r) + 0.7152 * linear(c.g) + 0.0722 * linear(c.b);
}

}  // namespace arttrack::sim
