#include "arttrack/tracker/camera.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "arttrack/tracker/error.h"

namespace arttrack {

CameraIntrinsics CameraIntrinsics::from_vertical_fov(int width, int height, double fovy_rad) {
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fy = 0.5 * height / std::tan(0.5 * fovy_rad);
  k.fx = k.fy;
  k.cx = 0.5 * width;
  k.cy = 0.5 * height;
  return k;
}

std::string CameraIntrinsics::problem() const {
  if (width <= 0 || height <= 0) return "width, height: must be positive";
  const auto focal = [](const char* name, double f, int size) -> std::string {
    constexpr double kDeg = 3.14159265358979323846 / 180;
    const double lo = 0.5 * size / std::tan(0.5 * kMaxFovDeg * kDeg);
    const double hi = 0.5 * size / std::tan(0.5 * kMinFovDeg * kDeg);
    if (f >= lo && f <= hi) return "";
    std::ostringstream out;
    out << name << ": " << f << " px must be in [" << lo << ", " << hi << "] for " << size
        << " pixels (a field of view from " << kMinFovDeg << " to " << kMaxFovDeg << " degrees)";
    return out.str();
  };
  const auto centre = [](const char* name, double c, int size) -> std::string {
    if (c >= 0 && c <= size) return "";
    std::ostringstream out;
    out << name << ": " << c << " px must be inside the image, in [0, " << size << "]";
    return out.str();
  };
  for (const std::string& p : {focal("fx", fx, width), focal("fy", fy, height),
                               centre("cx", cx, width), centre("cy", cy, height)})
    if (!p.empty()) return p;
  return "";
}

CameraIntrinsics CameraIntrinsics::scaled_to(int new_width, int new_height) const {
  const double sx = double(new_width) / width;
  const double sy = double(new_height) / height;
  CameraIntrinsics k;
  k.width = new_width;
  k.height = new_height;
  k.fx = fx * sx;
  k.fy = fy * sy;
  // Pixel edges scale, so the principal point scales as a continuous coordinate.
  k.cx = cx * sx;
  k.cy = cy * sy;
  return k;
}

DepthImage subsample_depth(const DepthImage& image, int new_width, int new_height) {
  ARTTRACK_CHECK_ARGUMENT(new_width > 0 && new_height > 0);
  DepthImage out(new_width, new_height);
  for (int v = 0; v < new_height; ++v) {
    // Source pixel whose centre is nearest the target pixel's centre.
    const int sv = std::min(image.height - 1, int((v + 0.5) * image.height / new_height));
    for (int u = 0; u < new_width; ++u) {
      const int su = std::min(image.width - 1, int((u + 0.5) * image.width / new_width));
      out.at(u, v) = image.at(su, sv);
    }
  }
  return out;
}

}  // namespace arttrack
