// Private to render/: the interface the EGL and GLFW back ends of GlContext implement, and the
// step both share once a context is current (load GL, check the version, fill GlInfo).
#pragma once

#include <array>
#include <memory>
#include <string>

#include "render/gl/GlContext.h"

namespace sph::render::gl {

struct GlContext::Impl {
  virtual ~Impl() = default;
  virtual void makeCurrent() = 0;
  virtual bool isWindow() const { return false; }
  virtual bool shouldClose() const { return false; }
  virtual void swapBuffers() {}
  virtual void pollEvents() {}
  virtual std::array<int, 2> framebufferSize() const { return {0, 0}; }
  virtual void setInputHandler(std::function<void(const InputEvent&)>) {}
  virtual void setTitle(const std::string&) {}
  GlInfo info;
};

namespace detail {

using GlProc = void (*)();
using GlGetProc = GlProc (*)(const char* name);

// Loads the GL functions through `getProc`, checks the version against `options` and returns the
// driver's strings. Throws GlUnavailable naming `platform` and what the driver offers.
GlInfo loadGl(GlGetProc getProc, const GlContextOptions& options, const std::string& platform);

std::unique_ptr<GlContext::Impl> createEglContext(const GlContextOptions& options);
std::unique_ptr<GlContext::Impl> createGlfwContext(const GlWindowOptions& options);

}  // namespace detail
}  // namespace sph::render::gl
