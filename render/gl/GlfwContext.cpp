// A window with an OpenGL 4.5 core context through GLFW (DESIGN.md, "Dependencies"), for the
// interactive replay of the renderer issue. Under Xvfb in tests, on llvmpipe through GLX.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <mutex>
#include <string>

#include "render/gl/GlContextImpl.h"
#include "render/gl/GlError.h"

namespace sph::render::gl::detail {
namespace {

std::mutex gGlfwMutex;
int gGlfwUsers = 0;
std::string gLastGlfwError;

void onGlfwError(int, const char* description) {
  gLastGlfwError = description ? description : "?";
}

// glfwInit/glfwTerminate are process-wide: counted so that windows can come and go.
void acquireGlfw() {
  std::lock_guard<std::mutex> lock(gGlfwMutex);
  if (gGlfwUsers == 0) {
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
      throw GlUnavailable("no window system: GLFW could not start (" + gLastGlfwError + ")");
    }
  }
  ++gGlfwUsers;
}

void releaseGlfw() {
  std::lock_guard<std::mutex> lock(gGlfwMutex);
  if (--gGlfwUsers == 0) glfwTerminate();
}

GlProc glfwProc(const char* name) {
  return reinterpret_cast<GlProc>(glfwGetProcAddress(name));
}

struct GlfwImpl final : GlContext::Impl {
  GLFWwindow* window = nullptr;
  bool acquired = false;

  ~GlfwImpl() override {
    if (window) glfwDestroyWindow(window);
    if (acquired) releaseGlfw();
  }
  void makeCurrent() override { glfwMakeContextCurrent(window); }
  bool isWindow() const override { return true; }
  bool shouldClose() const override { return glfwWindowShouldClose(window) != 0; }
  void swapBuffers() override { glfwSwapBuffers(window); }
  void pollEvents() override { glfwPollEvents(); }
  std::array<int, 2> framebufferSize() const override {
    std::array<int, 2> size{};
    glfwGetFramebufferSize(window, &size[0], &size[1]);
    return size;
  }
  std::function<void(const InputEvent&)> handler;
  void setTitle(const std::string& title) override { glfwSetWindowTitle(window, title.c_str()); }
  void setInputHandler(std::function<void(const InputEvent&)> h) override {
    handler = std::move(h);
    glfwSetWindowUserPointer(window, this);
    auto emit = [](GLFWwindow* w, const InputEvent& e) {
      auto* self = static_cast<GlfwImpl*>(glfwGetWindowUserPointer(w));
      if (self && self->handler) self->handler(e);
    };
    static auto forward = emit;  // captureless: usable from the C callbacks below
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
      InputEvent e;
      e.type = InputEvent::Type::Key, e.key = key, e.press = action != GLFW_RELEASE;
      forward(w, e);
    });
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
      InputEvent e;
      e.type = InputEvent::Type::MouseButton, e.key = button, e.press = action == GLFW_PRESS;
      glfwGetCursorPos(w, &e.x, &e.y);
      forward(w, e);
    });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
      InputEvent e;
      e.type = InputEvent::Type::CursorMove, e.x = x, e.y = y;
      forward(w, e);
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double x, double y) {
      InputEvent e;
      e.type = InputEvent::Type::Scroll, e.x = x, e.y = y;
      forward(w, e);
    });
  }
};

}  // namespace

std::unique_ptr<GlContext::Impl> createGlfwContext(const GlWindowOptions& options) {
  auto impl = std::make_unique<GlfwImpl>();
  acquireGlfw();
  impl->acquired = true;
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, options.major);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, options.minor);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debug ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  impl->window =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (!impl->window) {
    throw GlUnavailable("glfw: no window with OpenGL " + std::to_string(options.major) + "." +
                        std::to_string(options.minor) + " core (" + gLastGlfwError + ")");
  }
  impl->makeCurrent();
  impl->info = loadGl(glfwProc, options, "glfw");
  return impl;
}

}  // namespace sph::render::gl::detail
