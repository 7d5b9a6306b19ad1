#include "arttrack/sim/depth_compare.h"

#include <cmath>
#include <cstdio>

#include "arttrack/tracker/error.h"

namespace arttrack::sim {

double DepthAgreement::fraction_within() const {
  return pixels_both ? double(within_tolerance) / double(pixels_both) : 1.0;
}

double DepthAgreement::silhouette_iou() const {
  const long either = pixels_a + pixels_b - pixels_both;
  return either ? double(pixels_both) / double(either) : 1.0;
}

std::string DepthAgreement::summary() const {
  char buf[200];
  std::snprintf(buf, sizeof(buf),
                "a %ld px, b %ld px, both %ld px, %.2f%% within %.1f mm (max diff %.2f mm), "
                "silhouette IoU %.4f",
                pixels_a, pixels_b, pixels_both, 100.0 * fraction_within(), tolerance_m * 1e3,
                max_abs_difference_m * 1e3, silhouette_iou());
  return buf;
}

DepthAgreement compare_depth(const DepthImage& a, const DepthImage& b, double tolerance_m) {
  ARTTRACK_CHECK_ARGUMENT(a.width == b.width && a.height == b.height);
  DepthAgreement r;
  r.tolerance_m = tolerance_m;
  for (size_t i = 0; i < a.depth_m.size(); ++i) {
    const float za = a.depth_m[i], zb = b.depth_m[i];
    const bool ha = std::isfinite(za) && za > 0, hb = std::isfinite(zb) && zb > 0;
    r.pixels_a += ha;
    r.pixels_b += hb;
    if (!(ha && hb)) continue;
    ++r.pixels_both;
    const double diff = std::abs(double(za) - double(zb));
    r.within_tolerance += diff <= tolerance_m;
    r.max_abs_difference_m = std::max(r.max_abs_difference_m, diff);
  }
  return r;
}

}  // namespace arttrack::sim
