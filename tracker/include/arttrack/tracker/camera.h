// Pinhole camera intrinsics and depth images, shared by the tracker, the
// simulator and the tools.
//
// Frames: the camera's optical frame has z forward (along the optical axis),
// x right and y down. Depth is metres along the optical axis (planar depth,
// not ray length); 0 means no return.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace arttrack {

// Pinhole intrinsics in pixels. Pixel (u, v) covers [u, u+1) x [v, v+1); its
// centre is (u + 0.5, v + 0.5). A point (x, y, z) in the optical frame
// projects to (fx x / z + cx, fy y / z + cy).
struct CameraIntrinsics {
  int width = 0;
  int height = 0;
  double fx = 0;  // focal length, pixels
  double fy = 0;
  double cx = 0;  // principal point, pixels (W/2 for a centred one)
  double cy = 0;

  // Square pixels and a centred principal point from a vertical field of view
  // (the only intrinsics MuJoCo 2.2 cameras have).
  static CameraIntrinsics from_vertical_fov(int width, int height, double fovy_rad);

  // The same camera at another resolution (e.g. 640x480 subsampled to 80x60).
  CameraIntrinsics scaled_to(int new_width, int new_height) const;

  bool operator==(const CameraIntrinsics&) const = default;

  // Limits of a usable camera: the field of view of each axis,
  // 2 atan(width / (2 fx)) and 2 atan(height / (2 fy)), in [kMinFovDeg,
  // kMaxFovDeg], and the principal point inside the image (cx in [0, width],
  // cy in [0, height]).
  static constexpr double kMinFovDeg = 1;
  static constexpr double kMaxFovDeg = 170;
  // The first field ("width", "fx", "cx", ...) outside those limits, with
  // what would be right, as "fx: ..."; "" when the intrinsics are usable.
  std::string problem() const;
};

// A rectangle of pixels [u0, u1) x [v0, v1); empty when u0 >= u1 or v0 >= v1.
// The renderer returns the rectangle it drew; the likelihood scores only it.
struct PixelRect {
  int u0 = 0, v0 = 0, u1 = 0, v1 = 0;

  bool empty() const { return u0 >= u1 || v0 >= v1; }
  int width() const { return empty() ? 0 : u1 - u0; }
  int height() const { return empty() ? 0 : v1 - v0; }
  int area() const { return width() * height(); }
  // The smallest rectangle holding both.
  PixelRect united(const PixelRect& other) const {
    if (empty()) return other;
    if (other.empty()) return *this;
    return {u0 < other.u0 ? u0 : other.u0, v0 < other.v0 ? v0 : other.v0,
            u1 > other.u1 ? u1 : other.u1, v1 > other.v1 ? v1 : other.v1};
  }
};

// A depth image, row-major, metres along the optical axis, 0 for no return.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<float> depth_m;

  DepthImage() = default;
  DepthImage(int w, int h, float fill = 0.f)
      : width(w), height(h), depth_m(std::size_t(w) * h, fill) {}

  float& at(int u, int v) { return depth_m[std::size_t(v) * width + u]; }
  float at(int u, int v) const { return depth_m[std::size_t(v) * width + u]; }
  bool empty() const { return depth_m.empty(); }
};

// Subsamples by taking the centre pixel of each block (no averaging across
// depth edges, which would invent depths that are on no surface): target
// pixel u is source pixel floor((u + 0.5) W / w), clamped.
DepthImage subsample_depth(const DepthImage& image, int new_width, int new_height);
// The same into `out` (not `image`), in its storage: no allocation once `out`
// has held an image of this many pixels.
void subsample_depth(const DepthImage& image, int new_width, int new_height, DepthImage& out);

// The intrinsics of the image subsample_depth() returns, for a source image
// with intrinsics `source`. Not scaled_to(): the source pixel a block keeps
// has its centre up to half a source pixel from the block's centre (exactly
// half, always the same way, when the factor is even), so the subsampled
// pixels look along rays shifted by that much. The principal point takes the
// mean shift over the image: a render with scaled_to()'s intrinsics sits a
// quarter pixel off an image subsampled 2:1, which cost the true
// configuration 1,350 nats against one with the camera rolled by a degree
// and both shoulders turned back (docs/accuracy.md, "Consistency").
CameraIntrinsics subsampled_intrinsics(const CameraIntrinsics& source, int new_width,
                                       int new_height);

}  // namespace arttrack
