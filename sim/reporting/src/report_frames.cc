// The run report's kept depth frames: the observed depth in the colour map
// (near red, far blue, black: no return; Turbo from 0.1 up, clear of its
// near-black blue) with the estimate's silhouette
// edges in white, embedded as PNG data URIs, each with its colour bar.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>
#include <vector>

#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/internal/svg_chart.h"
#include "arttrack/sim/internal/text_format.h"
#include "report_sections.h"

namespace arttrack::sim::report {

namespace {

// The q-quantile of the valid depths (NaN if none).
double depth_quantile(std::vector<float>& z, double q) {
  if (z.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(z.begin(), z.end());
  return z[std::size_t(q * double(z.size() - 1))];
}

// The depth range the colours span, m. With an estimate, the depths of its
// render set the far end (98th percentile plus a quarter of the span): the
// robot, not the far wall, gets the colours. Without, the 2nd to 98th
// percentile of the whole image.
std::pair<double, double> depth_range(const DepthImage& observed, const DepthImage& estimate) {
  std::vector<float> all, robot;
  for (float z : observed.depth_m)
    if (std::isfinite(z) && z > 0) all.push_back(z);
  for (float z : estimate.depth_m)
    if (std::isfinite(z) && z > 0) robot.push_back(z);
  if (all.empty()) return {0.0, 1.0};
  const double near_all = depth_quantile(all, 0.02), far_all = depth_quantile(all, 0.98);
  double near_m = near_all, far_m = far_all;
  if (robot.size() >= 20) {
    const double near_robot = depth_quantile(robot, 0.02), far_robot = depth_quantile(robot, 0.98);
    near_m = std::min(near_all, near_robot);
    far_m = std::min(far_all, far_robot + 0.25 * (far_robot - near_m));
  }
  return {near_m, far_m > near_m + 0.01 ? far_m : near_m + 0.01};
}

// Observed depth in the scale's colours (black: no return), the estimate's
// silhouette edges in white (about 1/320 of the width thick).
std::vector<std::uint8_t> overlay_rgb(const DepthImage& observed, const DepthImage& estimate,
                                      const chart::ColourScale& scale) {
  const int w = observed.width, h = observed.height;
  std::vector<std::uint8_t> rgb(std::size_t(w) * h * 3, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const float z = observed.at(u, v);
      if (!(std::isfinite(z) && z > 0)) continue;
      const Rgb c = scale.colour(z);
      std::uint8_t* p = &rgb[(std::size_t(v) * w + u) * 3];
      p[0] = c.r, p[1] = c.g, p[2] = c.b;
    }
  if (estimate.width != w || estimate.height != h) return rgb;
  const int r = std::max(1, w / 320);
  auto covered = [&](int u, int v) {
    return u >= 0 && v >= 0 && u < w && v < h && estimate.at(u, v) > 0;
  };
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      if (!covered(u, v)) continue;
      bool edge = false;
      for (int dv = -r; dv <= r && !edge; ++dv)
        for (int du = -r; du <= r && !edge; ++du) edge = !covered(u + du, v + dv);
      if (edge) std::fill_n(&rgb[(std::size_t(v) * w + u) * 3], 3, std::uint8_t(255));
    }
  return rgb;
}

}  // namespace

void frames_section(std::ostream& o, const ScenarioResult& r) {
  o << "<h2>Kept depth frames</h2>\n";
  if (r.frames.empty()) {
    o << "<p>No depth frame was kept.</p>\n";
    return;
  }
  o << "<p>The depth image the trackers received (false colour: near red, far blue; black: no "
       "return), with the silhouette of the estimate rendered right after the tracker applied "
       "it drawn in white.</p>\n<div class=\"two\">\n";
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const KeptFrame& k = r.frames[i];
    o << "<figure>";
    if (k.observed.width > 0 && k.observed.height > 0 && !k.observed.empty()) {
      const auto [near_m, far_m] = depth_range(k.observed, k.estimate);
      chart::ColourScale scale;
      scale.lo = near_m;
      scale.hi = far_m;
      scale.reversed = true;  // near red
      scale.t_min = 0.1;      // far blue, not the near-black end
      const std::vector<std::uint8_t> png = encode_png_rgb(
          k.observed.width, k.observed.height, overlay_rgb(k.observed, k.estimate, scale));
      o << "<img alt=\"depth frame " << i << "\" width=\"" << k.observed.width << "\" height=\""
        << k.observed.height << "\" src=\"data:image/png;base64," << text::base64(png) << "\">\n";
      chart::colour_bar(o, "colours-" + std::to_string(i), scale, "depth, m (black: no return)");
    }
    o << "<figcaption>Frame " << i << ": captured at t = " << chart::fixed(k.stamp_s, 2)
      << " s, reached the trackers at " << chart::fixed(k.arrival_s, 2) << " s (run " << k.run
      << "); "
      << (k.estimate.empty() ? std::string("no estimate rendered")
                             : "white: the " + text::html_escape(k.estimate_method) + " estimate")
      << ".</figcaption></figure>\n";
  }
  o << "</div>\n";
}

}  // namespace arttrack::sim::report
