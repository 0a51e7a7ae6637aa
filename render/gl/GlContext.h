// The project's one OpenGL context layer (DESIGN.md, "Dependencies"): an OpenGL 4.5 core context,
// headless through EGL (Mesa's surfaceless platform, or the device platform of a GPU driver) or
// in a GLFW window. Creating one loads the GL functions (glad) and checks the version; every
// failure is a GlUnavailable with one line saying what failed (render/gl/GlError.h).
//
// Nothing creates a context behind the caller's back: the collision pass and the renderers take
// one only when the scene asks for them (DESIGN.md, "What a scene does not need is not run"), and
// createdCount() lets tests check that.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>

namespace sph::render::gl {

struct GlContextOptions {
  int major = 4, minor = 5;  // lowest core version accepted
  bool debug = false;        // debug context, GL errors reported through KHR_debug to stderr
};

struct GlWindowOptions : GlContextOptions {
  int width = 1280, height = 720;  // window size in screen coordinates
  std::string title = "sphsplat";
  bool visible = true;
};

// What the driver reported once the context was made current.
// Keyboard and mouse input of a window context (key codes are GLFW's: printable keys are their
// upper-case ASCII code, see the constants below).
struct InputEvent {
  enum class Type { Key, MouseButton, CursorMove, Scroll } type = Type::Key;
  int key = 0;          // Key: the key; MouseButton: 0 left, 1 right, 2 middle
  bool press = false;   // Key / MouseButton: pressed (or repeated) rather than released
  double x = 0, y = 0;  // CursorMove: window position; Scroll: offsets
};
namespace keys {
inline constexpr int kSpace = 32, kEscape = 256, kRight = 262, kLeft = 263, kDown = 264, kUp = 265,
                     kPageUp = 266, kPageDown = 267, kHome = 268, kEnd = 269;
}  // namespace keys

struct GlInfo {
  std::string platform;  // "egl-surfaceless", "egl-device", "glfw"
  std::string vendor, renderer, version;
  int major = 0, minor = 0;
};

class GlContext {
 public:
  // Headless context through EGL: surfaceless platform first, then each EGL device. Current on
  // return. Throws GlUnavailable.
  static GlContext headless(const GlContextOptions& options = {});
  // A window with a context (GLFW; X11 or Wayland). Current on return. Throws GlUnavailable.
  static GlContext window(const GlWindowOptions& options = {});

  GlContext(GlContext&&) noexcept;
  GlContext& operator=(GlContext&&) noexcept;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;
  ~GlContext();

  void makeCurrent();
  const GlInfo& info() const;

  // Window contexts only (no-ops / {0, 0} for headless ones).
  bool isWindow() const;
  bool shouldClose() const;
  void swapBuffers();
  void pollEvents();
  std::array<int, 2> framebufferSize() const;
  // Window contexts: where input goes (called from pollEvents()) and the title bar.
  void setInputHandler(std::function<void(const InputEvent&)> handler);
  void setTitle(const std::string& title);

  // Contexts this process has created so far, and how many are alive now.
  static int createdCount();
  static int liveCount();

  // The implementation behind a context (EGL or GLFW), defined in their own files.
  struct Impl;

 private:
  explicit GlContext(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace sph::render::gl
