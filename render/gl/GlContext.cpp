#include "render/gl/GlContext.h"

#include <glad/gl.h>

#include <atomic>
#include <cstdio>
#include <sstream>

#include "render/gl/GlContextImpl.h"
#include "render/gl/GlError.h"

namespace sph::render::gl {
namespace {

std::atomic<int> gCreated{0};
std::atomic<int> gLive{0};

const char* glString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "?";
}

void GLAD_API_PTR debugMessage(GLenum, GLenum type, GLuint, GLenum severity, GLsizei,
                               const GLchar* message, const void*) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  std::fprintf(stderr, "sphsplat: GL %s: %s\n", type == GL_DEBUG_TYPE_ERROR ? "error" : "debug",
               message);
}

}  // namespace

namespace detail {

GlInfo loadGl(GlGetProc getProc, const GlContextOptions& options, const std::string& platform) {
  // glad's loader checks the version the context reports and loads what it offers.
  const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(getProc));
  if (version == 0) {
    throw GlUnavailable(platform +
                        ": the OpenGL functions could not be loaded (glad found no GL version)");
  }
  GlInfo info;
  info.platform = platform;
  info.major = GLAD_VERSION_MAJOR(version);
  info.minor = GLAD_VERSION_MINOR(version);
  info.vendor = glString(GL_VENDOR);
  info.renderer = glString(GL_RENDERER);
  info.version = glString(GL_VERSION);
  if (info.major * 10 + info.minor < options.major * 10 + options.minor) {
    std::ostringstream m;
    m << "OpenGL " << options.major << "." << options.minor << " core is needed, but " << platform
      << " gives OpenGL " << info.major << "." << info.minor << " (" << info.renderer << ", "
      << info.version << ")";
    throw GlUnavailable(m.str());
  }
  if (options.debug && GLAD_GL_KHR_debug) {
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugMessage, nullptr);
  }
  return info;
}

}  // namespace detail

GlContext::GlContext(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {
  gCreated.fetch_add(1);
  gLive.fetch_add(1);
}

GlContext GlContext::headless(const GlContextOptions& options) {
  return GlContext(detail::createEglContext(options));
}

GlContext GlContext::window(const GlWindowOptions& options) {
  return GlContext(detail::createGlfwContext(options));
}

GlContext::GlContext(GlContext&& other) noexcept = default;
GlContext& GlContext::operator=(GlContext&& other) noexcept {
  if (this != &other) {
    if (impl_) gLive.fetch_sub(1);
    impl_ = std::move(other.impl_);
  }
  return *this;
}

GlContext::~GlContext() {
  if (impl_) gLive.fetch_sub(1);
}

void GlContext::makeCurrent() {
  impl_->makeCurrent();
}
const GlInfo& GlContext::info() const {
  return impl_->info;
}
bool GlContext::isWindow() const {
  return impl_->isWindow();
}
bool GlContext::shouldClose() const {
  return impl_->shouldClose();
}
void GlContext::swapBuffers() {
  impl_->swapBuffers();
}
void GlContext::pollEvents() {
  impl_->pollEvents();
}
void GlContext::setInputHandler(std::function<void(const InputEvent&)> handler) {
  impl_->setInputHandler(std::move(handler));
}
void GlContext::setTitle(const std::string& title) {
  impl_->setTitle(title);
}
std::array<int, 2> GlContext::framebufferSize() const {
  return impl_->framebufferSize();
}

int GlContext::createdCount() {
  return gCreated.load();
}
int GlContext::liveCount() {
  return gLive.load();
}

}  // namespace sph::render::gl
