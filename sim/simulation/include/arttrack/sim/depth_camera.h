// The simulated depth camera: MuJoCo's offscreen renderer at the scene's
// camera, read back as metric depth.
//
// Depth is metres along the optical axis (planar), 0 where nothing lies
// between the near and far planes; row 0 is the top of the image, as in
// DepthImage. Each DepthCamera owns its GL context (OSMesa or EGL) and
// MuJoCo rendering context; use it from one thread at a time.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>

#include "arttrack/sim/sim_model.h"
#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

// What to draw: everything the sensor would see, or the robot alone (its
// visual geometry), e.g. as the reference for the tracker's renderer.
enum class DepthContent { kScene, kRobot };

class DepthCamera {
 public:
  // Renders at width x height (0: the scene's resolution); the field of view
  // is the scene's either way. Throws std::runtime_error if no GL context can
  // be made.
  explicit DepthCamera(std::shared_ptr<const SimModel> model, int width = 0, int height = 0);
  ~DepthCamera();
  DepthCamera(const DepthCamera&) = delete;
  DepthCamera& operator=(const DepthCamera&) = delete;

  // Renders the state in `data` (poses must be current: mj_forward or
  // mj_kinematics done, as after Simulator steps). `out` is resized once and
  // reused; no allocation afterwards.
  void render(mjData* data, DepthContent content, DepthImage& out);

  // Pinhole intrinsics of the rendered images (square pixels, centred).
  const CameraIntrinsics& intrinsics() const;
  // The GL back end in use, e.g. "OSMesa".
  const char* gl_description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// MuJoCo's depth buffer value d in [0, 1] to metres along the optical axis,
// for clipping planes near_m and far_m (MuJoCo 2.2: a standard, not reversed,
// perspective depth buffer). d = 1 (nothing drawn) maps to 0.
inline float depth_buffer_to_m(float d, double near_m, double far_m) {
  if (d >= 1.f) return 0.f;
  return float(near_m / (1.0 - double(d) * (1.0 - near_m / far_m)));
}

}  // namespace arttrack::sim
