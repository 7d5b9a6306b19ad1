#include "arttrack/sim/depth_camera.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "gl_context.h"

namespace arttrack::sim {

struct DepthCamera::Impl {
  std::shared_ptr<const SimModel> model;
  int width, height;
  GlContext gl;  // first in, last out: MuJoCo's context is freed while it is current
  mjvScene scene;
  mjrContext context;
  mjvOption option;
  mjvCamera camera;
  CameraIntrinsics intrinsics;
  double near_m, far_m;
  int robot_group;            // visual geoms if the robot has any, else collision geoms
  std::vector<float> buffer;  // MuJoCo's depth buffer, bottom row first

  Impl(std::shared_ptr<const SimModel> m, int w, int h)
      : model(std::move(m)), width(w), height(h), gl(w, h) {}
};

DepthCamera::DepthCamera(std::shared_ptr<const SimModel> model, int width, int height) {
  if (width <= 0 || height <= 0) {
    width = model->scene.width;
    height = model->scene.height;
  }
  impl_ = std::make_unique<Impl>(std::move(model), width, height);
  Impl& s = *impl_;
  const mjModel* m = s.model->mj.get();

  mjv_defaultScene(&s.scene);
  mjv_makeScene(m, &s.scene, 4000);
  mjr_defaultContext(&s.context);
  // The offscreen buffer is sized from the model; a by-value (shallow) copy
  // with this camera's size lets one model serve any resolution.
  mjModel sized = *m;
  sized.vis.global.offwidth = width;
  sized.vis.global.offheight = height;
  mjr_makeContext(&sized, &s.context, mjFONTSCALE_50);
  mjr_setBuffer(mjFB_OFFSCREEN, &s.context);
  if (s.context.currentBuffer != mjFB_OFFSCREEN || s.context.offWidth < width ||
      s.context.offHeight < height) {
    mjr_freeContext(&s.context);
    mjv_freeScene(&s.scene);
    throw std::runtime_error(std::string("MuJoCo: no offscreen framebuffer on ") +
                             s.gl.description());
  }
  // Depth only: no shadows, reflections, skybox or fog to pay for.
  s.scene.flags[mjRND_SHADOW] = 0;
  s.scene.flags[mjRND_REFLECTION] = 0;
  s.scene.flags[mjRND_SKYBOX] = 0;
  s.scene.flags[mjRND_FOG] = 0;
  // A camera sees an open surface from either side (SimModel::render_both_sides).
  s.scene.flags[mjRND_CULL_FACE] = s.model->render_both_sides ? 0 : 1;
  mjv_defaultOption(&s.option);
  mjv_defaultCamera(&s.camera);
  s.camera.type = mjCAMERA_FIXED;
  s.camera.fixedcamid = s.model->camera_id;

  // The near and far planes MuJoCo draws with, from the pinned extent.
  s.near_m = m->vis.map.znear * m->stat.extent;
  s.far_m = m->vis.map.zfar * m->stat.extent;
  s.intrinsics = CameraIntrinsics::from_vertical_fov(width, height, s.model->scene.fovy_rad);
  s.robot_group = kGroupRobotCollision;
  for (int g = 0; g < m->ngeom; ++g)
    if (m->geom_group[g] == kGroupRobotVisual) s.robot_group = kGroupRobotVisual;
  s.buffer.resize(size_t(width) * height);
}

DepthCamera::~DepthCamera() {
  impl_->gl.make_current();
  mjr_freeContext(&impl_->context);
  mjv_freeScene(&impl_->scene);
}

void DepthCamera::render(mjData* data, DepthContent content, DepthImage& out) {
  Impl& s = *impl_;
  s.gl.make_current();
  for (int g = 0; g < mjNGROUP; ++g) s.option.geomgroup[g] = 0;
  s.option.geomgroup[s.robot_group] = 1;
  if (content == DepthContent::kScene) {
    s.option.geomgroup[kGroupScene] = 1;
    s.option.geomgroup[kGroupOccluder] = 1;
  }
  mjv_updateScene(s.model->mj.get(), data, &s.option, nullptr, &s.camera, mjCAT_ALL, &s.scene);
  // No lights: depth does not depend on them, and lighting every vertex was
  // a quarter of a frame (bench_sim, 160x120 scene: 6.0 -> 4.3 ms).
  s.scene.nlight = 0;
  const mjrRect viewport{0, 0, s.width, s.height};
  mjr_render(viewport, &s.scene, &s.context);
  mjr_readPixels(nullptr, s.buffer.data(), viewport, &s.context);

  if (out.width != s.width || out.height != s.height) out = DepthImage(s.width, s.height);
  // OpenGL's rows run bottom-up; DepthImage's top-down.
  for (int v = 0; v < s.height; ++v) {
    const float* row = s.buffer.data() + size_t(s.height - 1 - v) * s.width;
    float* dst = out.depth_m.data() + size_t(v) * s.width;
    for (int u = 0; u < s.width; ++u) dst[u] = depth_buffer_to_m(row[u], s.near_m, s.far_m);
  }
}

const CameraIntrinsics& DepthCamera::intrinsics() const { return impl_->intrinsics; }

const char* DepthCamera::gl_description() const { return impl_->gl.description(); }

}  // namespace arttrack::sim
