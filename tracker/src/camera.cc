#include "arttrack/tracker/camera.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"

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
    const double lo = 0.5 * size / std::tan(0.5 * kMaxFovDeg * kRadPerDeg);
    const double hi = 0.5 * size / std::tan(0.5 * kMinFovDeg * kRadPerDeg);
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

namespace {

// The source pixel subsample_depth() keeps for target pixel i: the one under
// the target pixel's centre.
int subsample_source_index(int i, int new_size, int size) {
  return std::min(size - 1, int((i + 0.5) * size / new_size));
}

// Mean over the target pixels of (kept source pixel's centre - target
// pixel's centre), in source pixels.
double mean_subsample_shift(int new_size, int size) {
  double sum = 0;
  for (int i = 0; i < new_size; ++i)
    sum += (subsample_source_index(i, new_size, size) + 0.5) - (i + 0.5) * size / new_size;
  return sum / new_size;
}

}  // namespace

DepthImage subsample_depth(const DepthImage& image, int new_width, int new_height) {
  DepthImage out;
  subsample_depth(image, new_width, new_height, out);
  return out;
}

void subsample_depth(const DepthImage& image, int new_width, int new_height, DepthImage& out) {
  ARTTRACK_CHECK_ARGUMENT(new_width > 0 && new_height > 0 && &out != &image);
  out.width = new_width;
  out.height = new_height;
  out.depth_m.resize(std::size_t(new_width) * new_height);
  for (int v = 0; v < new_height; ++v) {
    const int sv = subsample_source_index(v, new_height, image.height);
    for (int u = 0; u < new_width; ++u)
      out.at(u, v) = image.at(subsample_source_index(u, new_width, image.width), sv);
  }
}

CameraIntrinsics subsampled_intrinsics(const CameraIntrinsics& source, int new_width,
                                       int new_height) {
  CameraIntrinsics k = source.scaled_to(new_width, new_height);
  if (new_width == source.width && new_height == source.height) return k;
  // A point at source x = fx X / Z + cx is seen by the target pixel whose
  // kept source pixel is centred there: target x = (x - shift) / scale.
  k.cx -= mean_subsample_shift(new_width, source.width) * new_width / source.width;
  k.cy -= mean_subsample_shift(new_height, source.height) * new_height / source.height;
  return k;
}

}  // namespace arttrack
