// Headless OpenGL through EGL (DESIGN.md, "Dependencies"): Mesa's surfaceless platform (llvmpipe
// on machines without a GPU, the GPU driver otherwise), then the EGL device platform that GPU
// drivers without it offer. No window system, no surface: the context renders into framebuffer
// objects only. glad's loader opens libEGL.so.1 at run time, so its absence is a message too.
#include <glad/egl.h>

#include <cstring>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "render/gl/GlContextImpl.h"
#include "render/gl/GlError.h"

namespace sph::render::gl::detail {
namespace {

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default: {
      std::ostringstream s;
      s << "EGL error 0x" << std::hex << e;
      return s.str();
    }
  }
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

// Displays are shared by every context on them; eglTerminate would destroy the others' contexts,
// so a display is terminated when its last context goes.
std::mutex gDisplayMutex;
std::vector<std::pair<EGLDisplay, int>> gDisplayUsers;

void retainDisplay(EGLDisplay d) {
  std::lock_guard<std::mutex> lock(gDisplayMutex);
  for (auto& [display, users] : gDisplayUsers) {
    if (display == d) return void(++users);
  }
  gDisplayUsers.emplace_back(d, 1);
}

void releaseDisplay(EGLDisplay d) {
  std::lock_guard<std::mutex> lock(gDisplayMutex);
  for (std::size_t i = 0; i < gDisplayUsers.size(); ++i) {
    if (gDisplayUsers[i].first != d || --gDisplayUsers[i].second > 0) continue;
    eglTerminate(d);
    gDisplayUsers.erase(gDisplayUsers.begin() + static_cast<long>(i));
    return;
  }
}

struct Display {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
};

// The first display that initialises: surfaceless, then each device. `tried` collects why the
// others failed, for the message when none does.
Display openDisplay(std::string& tried) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto attempt = [&](EGLenum platform, void* native, const std::string& name) -> Display {
    // Before a display exists glad cannot know the EGL version, so the 1.5 entry point may be
    // missing; EGL_EXT_platform_base offers the same call.
    EGLDisplay d = EGL_NO_DISPLAY;
    if (eglGetPlatformDisplay)
      d = eglGetPlatformDisplay(platform, native, nullptr);
    else if (eglGetPlatformDisplayEXT)
      d = eglGetPlatformDisplayEXT(platform, native, nullptr);
    if (d == EGL_NO_DISPLAY) {
      tried += (tried.empty() ? "" : "; ") + name + ": no display";
      return {};
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor)) {
      tried += (tried.empty() ? "" : "; ") + name + ": eglInitialize failed (" +
               eglErrorName(eglGetError()) + ")";
      return {};
    }
    return {d, name};
  };
  if (hasExtension(client, "EGL_MESA_platform_surfaceless")) {
    Display d = attempt(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "egl-surfaceless");
    if (d.display != EGL_NO_DISPLAY) return d;
  } else {
    tried += "egl-surfaceless: not offered";
  }
  if (hasExtension(client, "EGL_EXT_platform_device") && eglQueryDevicesEXT) {
    EGLint count = 0;
    eglQueryDevicesEXT(0, nullptr, &count);
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    if (count > 0) eglQueryDevicesEXT(count, devices.data(), &count);
    for (EGLint i = 0; i < count; ++i) {
      Display d =
          attempt(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<std::size_t>(i)], "egl-device");
      if (d.display != EGL_NO_DISPLAY) return d;
    }
    if (count == 0) tried += "; egl-device: no devices";
  } else {
    tried += "; egl-device: not offered";
  }
  return {};
}

// The version string of the best context the display gives without asking for one, for the
// "version too low" message.
std::string probeVersion(EGLDisplay display, EGLConfig config) {
  EGLContext ctx = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
  if (ctx == EGL_NO_CONTEXT) return "no desktop OpenGL context at all";
  std::string version = "an unknown version";
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
    using GetString = const unsigned char* (*)(unsigned int);
    auto getString = reinterpret_cast<GetString>(eglGetProcAddress("glGetString"));
    const unsigned char* s = getString ? getString(0x1F02 /* GL_VERSION */) : nullptr;
    if (s) version = "OpenGL " + std::string(reinterpret_cast<const char*>(s));
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  eglDestroyContext(display, ctx);
  return version;
}

GlProc eglProc(const char* name) {
  return reinterpret_cast<GlProc>(eglGetProcAddress(name));
}

struct EglImpl final : GlContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;

  ~EglImpl() override {
    if (context != EGL_NO_CONTEXT) {
      if (eglGetCurrentContext() == context) {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      }
      eglDestroyContext(display, context);
    }
    if (display != EGL_NO_DISPLAY) releaseDisplay(display);
  }

  void makeCurrent() override {
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      throw GlUnavailable("eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")");
    }
  }
};

}  // namespace

std::unique_ptr<GlContext::Impl> createEglContext(const GlContextOptions& options) {
  if (!gladLoaderLoadEGL(EGL_NO_DISPLAY)) {
    throw GlUnavailable(
        "no EGL library: libEGL.so.1 could not be loaded (install libegl1 and a driver, e.g. "
        "libegl-mesa0)");
  }
  std::string tried;
  Display found = openDisplay(tried);
  if (found.display == EGL_NO_DISPLAY) {
    throw GlUnavailable("no EGL display (" + tried + ")");
  }
  auto impl = std::make_unique<EglImpl>();
  impl->display = found.display;
  retainDisplay(found.display);
  // Reload with the display: its version and extensions decide which functions exist.
  gladLoaderLoadEGL(found.display);
  const char* extensions = eglQueryString(found.display, EGL_EXTENSIONS);
  if (!hasExtension(extensions, "EGL_KHR_surfaceless_context")) {
    throw GlUnavailable(found.platform +
                        ": the EGL display cannot make a context current without a surface (no "
                        "EGL_KHR_surfaceless_context)");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    throw GlUnavailable(found.platform +
                        ": the EGL display offers no desktop OpenGL (eglBindAPI failed)");
  }
  // No surface type: the default (EGL_WINDOW_BIT) would exclude surfaceless configs.
  const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                     EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (!eglChooseConfig(found.display, configAttributes, &config, 1, &configs) || configs == 0) {
    throw GlUnavailable(found.platform + ": no EGL config renders desktop OpenGL");
  }
  std::vector<EGLint> attributes = {
      EGL_CONTEXT_MAJOR_VERSION,       options.major,
      EGL_CONTEXT_MINOR_VERSION,       options.minor,
      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
  if (options.debug) attributes.insert(attributes.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
  attributes.push_back(EGL_NONE);
  impl->context = eglCreateContext(found.display, config, EGL_NO_CONTEXT, attributes.data());
  if (impl->context == EGL_NO_CONTEXT) {
    const std::string error = eglErrorName(eglGetError());
    std::ostringstream m;
    m << "OpenGL " << options.major << "." << options.minor << " core is needed, but "
      << found.platform << " refused it (" << error << "); it offers "
      << probeVersion(found.display, config);
    throw GlUnavailable(m.str());
  }
  impl->makeCurrent();
  impl->info = loadGl(eglProc, options, found.platform);
  return impl;
}

}  // namespace sph::render::gl::detail
