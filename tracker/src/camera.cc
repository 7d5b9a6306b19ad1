#include "arttrack/tracker/camera.h"

#include <algorithm>
#include <cassert>
#include <cmath>

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
  assert(new_width > 0 && new_height > 0);
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
