#include "gl_context.h"

#include <stdexcept>
#include <string>
#include <vector>

#if defined(ARTTRACK_GL_OSMESA)
#include <GL/osmesa.h>
#elif defined(ARTTRACK_GL_EGL)
#include <EGL/egl.h>
#include <EGL/eglext.h>
#else
#error "Define ARTTRACK_GL_OSMESA or ARTTRACK_GL_EGL (set by sim/CMakeLists.txt)"
#endif

namespace arttrack::sim {

#if defined(ARTTRACK_GL_OSMESA)

struct GlContext::Impl {
  OSMesaContext context = nullptr;
  // OSMesa needs a default framebuffer to make a context current; MuJoCo
  // renders into its own offscreen framebuffer object, not into this one.
  std::vector<unsigned char> buffer;
  int width = 0, height = 0;
};

GlContext::GlContext(int width, int height) : impl_(std::make_unique<Impl>()) {
  impl_->width = width;
  impl_->height = height;
  impl_->buffer.resize(size_t(width) * height * 4);
  impl_->context = OSMesaCreateContextExt(GL_RGBA, 24, 8, 8, nullptr);
  if (!impl_->context) throw std::runtime_error("OSMesa: cannot create a GL context");
  make_current();
}

GlContext::~GlContext() {
  if (impl_->context) OSMesaDestroyContext(impl_->context);
}

void GlContext::make_current() {
  if (OSMesaGetCurrentContext() == impl_->context) return;
  if (!OSMesaMakeCurrent(impl_->context, impl_->buffer.data(), GL_UNSIGNED_BYTE, impl_->width,
                         impl_->height))
    throw std::runtime_error("OSMesa: cannot make the GL context current");
}

const char* GlContext::description() const { return "OSMesa"; }

#else  // EGL

namespace {

bool has_extension(const char* list, const std::string& name) {
  if (!list) return false;
  const std::string s = std::string(" ") + list + " ";
  return s.find(" " + name + " ") != std::string::npos;
}

}  // namespace

struct GlContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  const char* description = "";
};

GlContext::GlContext(int width, int height) : impl_(std::make_unique<Impl>()) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw std::runtime_error("EGL: no eglGetPlatformDisplayEXT");

  // A hardware device first: software devices are what surfaceless gives too.
  if (has_extension(client, "EGL_EXT_device_enumeration") &&
      has_extension(client, "EGL_EXT_platform_device")) {
    auto query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (query_devices && query_device_string && query_devices(16, devices, &count)) {
      for (EGLint i = 0; i < count && impl_->display == EGL_NO_DISPLAY; ++i) {
        if (has_extension(query_device_string(devices[i], EGL_EXTENSIONS),
                          "EGL_MESA_device_software"))
          continue;
        EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) {
          impl_->display = d;
          impl_->description = "EGL device (GPU)";
        }
      }
    }
  }
  if (impl_->display == EGL_NO_DISPLAY && has_extension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d =
        get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) {
      impl_->display = d;
      impl_->description = "EGL surfaceless (Mesa)";
    }
  }
  if (impl_->display == EGL_NO_DISPLAY)
    throw std::runtime_error("EGL: no GPU device and no Mesa surfaceless platform");

  const EGLint config_attribs[] = {EGL_SURFACE_TYPE,
                                   EGL_PBUFFER_BIT,
                                   EGL_RED_SIZE,
                                   8,
                                   EGL_GREEN_SIZE,
                                   8,
                                   EGL_BLUE_SIZE,
                                   8,
                                   EGL_ALPHA_SIZE,
                                   8,
                                   EGL_DEPTH_SIZE,
                                   24,
                                   EGL_STENCIL_SIZE,
                                   8,
                                   EGL_RENDERABLE_TYPE,
                                   EGL_OPENGL_BIT,
                                   EGL_NONE};
  EGLConfig config;
  EGLint n = 0;
  if (!eglChooseConfig(impl_->display, config_attribs, &config, 1, &n) || n < 1)
    throw std::runtime_error("EGL: no RGBA8/depth24 OpenGL config");
  if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error("EGL: cannot bind OpenGL");
  // MuJoCo 2.2 renders with the compatibility profile: the default context.
  impl_->context = eglCreateContext(impl_->display, config, EGL_NO_CONTEXT, nullptr);
  if (impl_->context == EGL_NO_CONTEXT) throw std::runtime_error("EGL: cannot create a context");
  (void)width;
  (void)height;
  make_current();
}

GlContext::~GlContext() {
  if (impl_->display == EGL_NO_DISPLAY) return;
  eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (impl_->context != EGL_NO_CONTEXT) eglDestroyContext(impl_->display, impl_->context);
  // No eglTerminate: the display is one per process and other contexts
  // (other cameras) may still live on it.
}

void GlContext::make_current() {
  if (eglGetCurrentContext() == impl_->context) return;
  // Surfaceless (EGL_KHR_surfaceless_context): MuJoCo draws into its own FBO.
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    throw std::runtime_error("EGL: cannot make the context current");
}

const char* GlContext::description() const { return impl_->description; }

#endif

}  // namespace arttrack::sim
