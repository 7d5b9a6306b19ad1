// An offscreen OpenGL context for MuJoCo's renderer: OSMesa (software,
// default) or EGL (a GPU found through device enumeration, else Mesa's
// surfaceless platform), chosen at build time by ARTTRACK_GL_BACKEND.
#pragma once

#include <memory>

namespace arttrack::sim {

class GlContext {
 public:
  // Creates the context and makes it current on this thread. Failure (no GL
  // available on this machine) throws std::runtime_error.
  GlContext(int width, int height);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes this context current on the calling thread (a no-op if it is).
  void make_current();

  // Which back end and device, e.g. "OSMesa" or "EGL device (GPU)".
  const char* description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace arttrack::sim
