// The GL context layer (render/): a headless OpenGL 4.5 core context through EGL, a GLFW window
// (under Xvfb when there is no display), one clear line when a context cannot be had, move-only
// handles, and shader errors that name the shader's file and line, includes resolved.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>
#include <type_traits>

#include "render/gl/GlContext.h"
#include "render/gl/GlError.h"
#include "render/gl/GlHandle.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/Shader.h"
#include "tests/TestSupport.h"

namespace sph::render::gl {
namespace {

std::string tempDirectory() {
  return test::makeTempDirectory("sphsplat-shaders");
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

TEST(GlContext, HeadlessIsOpenGl45Core) {
  const int created = GlContext::createdCount();
  {
    GlContext context = GlContext::headless();
    EXPECT_GE(context.info().major * 10 + context.info().minor, 45) << context.info().version;
    EXPECT_FALSE(context.info().renderer.empty());
    EXPECT_EQ(context.info().platform.rfind("egl-", 0), 0u) << context.info().platform;
    EXPECT_FALSE(context.isWindow());
    EXPECT_EQ(GlContext::createdCount(), created + 1);
    EXPECT_EQ(GlContext::liveCount(), 1);
    std::printf("    %s: %s, %s\n", context.info().platform.c_str(),
                context.info().renderer.c_str(), context.info().version.c_str());
    GlContext moved = std::move(context);
    EXPECT_EQ(GlContext::liveCount(), 1);
  }
  EXPECT_EQ(GlContext::liveCount(), 0);
  // A second one after the first is gone works as well (the display is shared, then released).
  GlContext again = GlContext::headless();
  EXPECT_GE(again.info().major, 4);
}

TEST(GlContext, TooHighAVersionIsOneClearLine) {
  GlContextOptions options;
  options.major = 9, options.minor = 9;
  try {
    GlContext::headless(options);
    FAIL() << "an OpenGL 9.9 context cannot exist";
  } catch (const GlUnavailable& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("OpenGL 9.9 core is needed"), std::string::npos) << what;
    EXPECT_NE(what.find("offers"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line";
  }
  EXPECT_EQ(GlContext::liveCount(), 0);
}

// Xvfb for the window test when the machine has no display; stopped (by its pid) at the end.
class VirtualDisplay {
 public:
  VirtualDisplay() {
    if (std::getenv("DISPLAY")) return;
    for (int n = 91; n < 99 && pid_ <= 0; ++n) {
      const std::string socket = "/tmp/.X11-unix/X" + std::to_string(n);
      struct stat st;
      if (stat(socket.c_str(), &st) == 0) continue;  // taken
      const std::string display = ":" + std::to_string(n);
      pid_ = fork();
      if (pid_ == 0) {
        execlp("Xvfb", "Xvfb", display.c_str(), "-screen", "0", "320x240x24", "-nolisten", "tcp",
               static_cast<char*>(nullptr));
        _exit(127);
      }
      for (int wait = 0; wait < 100; ++wait) {
        if (stat(socket.c_str(), &st) == 0) {
          setenv("DISPLAY", display.c_str(), 1);
          return;
        }
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) break;  // Xvfb gave up or is missing
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      stop();
    }
  }
  ~VirtualDisplay() { stop(); }
  bool available() const { return std::getenv("DISPLAY") != nullptr; }

 private:
  void stop() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
      unsetenv("DISPLAY");
    }
    pid_ = -1;
  }
  pid_t pid_ = -1;
};

TEST(GlContext, WindowThroughGlfw) {
  VirtualDisplay display;
  if (!display.available()) GTEST_SKIP() << "no display and no Xvfb to make one";
  GlWindowOptions options;
  options.width = 160, options.height = 120;
  options.visible = false;
  GlContext window = GlContext::window(options);
  EXPECT_TRUE(window.isWindow());
  EXPECT_EQ(window.info().platform, "glfw");
  EXPECT_GE(window.info().major * 10 + window.info().minor, 45) << window.info().version;
  EXPECT_EQ(window.framebufferSize()[0], 160);
  EXPECT_EQ(window.framebufferSize()[1], 120);
  glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  unsigned char pixel[4] = {0, 0, 0, 0};
  readPixels(0, GL_BACK, {10, 10, 1, 1}, GL_RGBA, GL_UNSIGNED_BYTE, pixel);
  EXPECT_NEAR(pixel[2], 191, 1);
  window.swapBuffers();
  window.pollEvents();
  EXPECT_FALSE(window.shouldClose());
}

TEST(GlHandles, MoveOnlyAndDeletedOnce) {
  static_assert(!std::is_copy_constructible_v<Buffer> && !std::is_copy_assignable_v<Buffer>);
  static_assert(std::is_nothrow_move_constructible_v<Texture> &&
                std::is_nothrow_move_assignable_v<Texture>);
  GlContext context = GlContext::headless();
  Buffer a = Buffer::create();
  const GLuint id = a.id();
  ASSERT_NE(id, 0u);
  EXPECT_TRUE(glIsBuffer(id));
  Buffer b = std::move(a);
  EXPECT_EQ(a.id(), 0u);
  EXPECT_EQ(b.id(), id);
  b = Buffer::create();  // the first is deleted here
  EXPECT_FALSE(glIsBuffer(id));
  b.reset();
  EXPECT_FALSE(b);
}

TEST(ShaderLog, MapsDriverFormatsToFileAndLine) {
  // Expanded text: line 1-2 from a.vert, 3-4 from common.glsl (its lines 1-2), 5 from a.vert (4).
  ExpandedShader source;
  source.files = {"shaders/a.vert", "shaders/common.glsl"};
  source.origin = {{0, 1}, {0, 2}, {1, 1}, {1, 2}, {0, 4}};
  EXPECT_EQ(mapShaderLog("0:4(12): error: `x' undeclared\n", source),
            "shaders/common.glsl:2:12: error: `x' undeclared\n");
  EXPECT_EQ(mapShaderLog("0(5) : error C1008: undefined variable \"y\"\n", source),
            "shaders/a.vert:4: error C1008: undefined variable \"y\"\n");
  EXPECT_EQ(mapShaderLog("ERROR: 0:3: 'z' : undeclared identifier\n", source),
            "shaders/common.glsl:1: error: 'z' : undeclared identifier\n");
  EXPECT_EQ(mapShaderLog("something else\n", source), "something else\n");
}

TEST(Shader, CompileErrorNamesFileAndLineThroughIncludes) {
  GlContext context = GlContext::headless();
  const std::string dir = tempDirectory();
  writeFile(
      dir + "/common.glsl",
      "// shared\nfloat twice(float x) { return 2.0 * x; }\nfloat broken() { return missing; }\n");
  writeFile(dir + "/good.vert",
            "#version 450 core\n#include \"twice.glsl\"\nvoid main() { gl_Position = "
            "vec4(twice(1.0)); }\n");
  writeFile(dir + "/twice.glsl", "float twice(float x) { return 2.0 * x; }\n");
  writeFile(
      dir + "/uses_common.vert",
      "#version 450 core\n#include \"common.glsl\"\nvoid main() { gl_Position = vec4(0.0); }\n");
  writeFile(dir + "/broken.vert",
            "#version 450 core\n#include \"twice.glsl\"\n\nvoid main() {\n  gl_Position = "
            "vec4(twice(1.0)) + oops;\n}\n");
  writeFile(dir + "/missing_include.vert",
            "#version 450 core\n\n#include \"nowhere.glsl\"\nvoid main() {}\n");
  const ShaderLibrary library = ShaderLibrary::directory(dir);

  EXPECT_NE(buildProgram(library, {{ShaderStage::Vertex, "good.vert"}}, "good").id(), 0u);
  auto messageOf = [&](const char* file) -> std::string {
    try {
      buildProgram(library, {{ShaderStage::Vertex, file}}, "test");
    } catch (const ShaderError& e) {
      return e.what();
    }
    return "no error";
  };
  // The error in the stage file itself: its own line 5, though an include came before it.
  const std::string inMain = messageOf("broken.vert");
  EXPECT_EQ(inMain.rfind(dir + "/broken.vert:5:", 0), 0u) << inMain;
  EXPECT_NE(inMain.find("oops"), std::string::npos) << inMain;
  // The error inside an included file: that file and its line.
  const std::string inInclude = messageOf("uses_common.vert");
  EXPECT_EQ(inInclude.rfind(dir + "/common.glsl:3:", 0), 0u) << inInclude;
  // An include that does not exist: the file and line of the #include.
  const std::string missing = messageOf("missing_include.vert");
  EXPECT_NE(missing.find("nowhere.glsl"), std::string::npos) << missing;
  for (const std::string& m : {inMain, inInclude, missing})
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

}  // namespace
}  // namespace sph::render::gl
