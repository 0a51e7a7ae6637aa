// Particle lights (seed 004) as a user meets them: a small fireflies run draws lit frames, `render`
// names the light volume and `compare` prints the lights' error figures (trilinear beats nearest
// against the exact sum where the walls lie on voxel faces) with a sheet of pictures; culling to the view changes no pixel; a scene
// without `lights` has no light code on its way; bad `lights` keys are one line and exit 2.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <regex>
#include <string>
#include <vector>

#include "io/exports/Png.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using test::runSphsplat;

// The shipped fireflies scene made small: 4096 lights, 34^3 voxels of 4 cm, 160 x 120 pixels.
const char* kSmall =
    " --set solver.spacing=0.02 --set lights.emitter.count=4096 --set lights.volume.voxel_size=0.04"
    " --set lights.volume.min=[-0.68,-0.04,-0.68] --set lights.volume.voxels=34"
    " --set lights.range=0.1 --set lights.attenuation[2]=200 --set lights.intensity=0.15"
    " --set render.width=160 --set render.height=120";

class LightsCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::writeTempFile("", "") + "-dir";
    ::mkdir(dir_.c_str(), 0755);
    const auto r = runSphsplat("run " + test::sourcePath("scenes/fireflies.json") + kSmall +
                               " --end 0.1 -q --output " + dir_ + "/ff.h5");
    ASSERT_EQ(r.exitCode, 0) << r.output;
  }
  static std::string dir_;
};
std::string LightsCli::dir_;

TEST_F(LightsCli, RenderNamesTheLightsAndDrawsLitFrames) {
  const auto r = runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ + "/frames");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("particle lights: 4096 from an emitter, 34 x 34 x 34 voxels"),
            std::string::npos)
      << r.output;
  int w = 0, h = 0;
  const auto rgb = io::exports::readPng(dir_ + "/frames/fireflies_quad_00001.png", w, h);
  ASSERT_EQ(w, 160);
  // A dark room (room_light 0.1) with warm spots: some pixels far brighter in red than blue.
  int warm = 0;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3)
    warm += rgb[i] > 90 && rgb[i] > rgb[i + 2] + 30;
  EXPECT_GT(warm, 20) << "pixels lit by the fireflies";
}

TEST_F(LightsCli, CompareRanksTheFiltersAgainstTheExactSum) {
  const auto r =
      runSphsplat("compare " + dir_ + "/ff.h5 --frame last --size 160x120 --out " + dir_);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::smatch m;
  auto psnr = [&](const std::string& name) {
    const std::regex row("\\n +" + name + " +[0-9.]+ \\| +([0-9.]+) ");
    EXPECT_TRUE(std::regex_search(r.output, m, row)) << name << "\n" << r.output;
    return std::stod(m[1]);
  };
  // This small variant's volume puts the floor and walls on voxel faces (kSmall), where nearest
  // speckles and trilinear reads both sides evenly (docs/lights.md, "Surfaces on voxel faces").
  EXPECT_GT(psnr("trilinear"), psnr("nearest") + 1.0) << r.output;
  int w = 0, h = 0;
  io::exports::readPng(dir_ + "/fireflies_lights_compare_00001.png", w, h);
  EXPECT_GT(w, 6 * 160) << "exact + five filters side by side";
}

// The PNGs' pixels as ints (3 per pixel).
std::vector<int> pixels(const std::string& png) {
  int w = 0, h = 0;
  const auto rgb = io::exports::readPng(png, w, h);
  return std::vector<int>(rgb.begin(), rgb.end());
}

// The share of pixels that differ by more than one 8-bit step in some channel.
double differing(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size() || a.empty()) return 1.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); i += 3)
    n += std::abs(a[i] - b[i]) > 1 || std::abs(a[i + 1] - b[i + 1]) > 1 ||
         std::abs(a[i + 2] - b[i + 2]) > 1;
  return static_cast<double>(n) / static_cast<double>(a.size() / 3);
}

// lights.pipeline "deferred" on replay: `render` names it and draws the forward picture but for
// the few pixels of the opaque quad-splat water, which the lighting pass lights per pixel where
// the forward splats are lit per vertex (docs/lights.md, "Deferred").
TEST_F(LightsCli, RenderDeferredDrawsTheForwardPicture) {
  const auto r = runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ +
                             "/deferred --set lights.pipeline=deferred");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("deferred (G-buffer + lighting pass)"), std::string::npos) << r.output;
  const auto forward =
      runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ + "/forward");
  ASSERT_EQ(forward.exitCode, 0) << forward.output;
  const double share = differing(pixels(dir_ + "/forward/fireflies_quad_00001.png"),
                                 pixels(dir_ + "/deferred/fireflies_quad_00001.png"));
  EXPECT_LT(share, 0.02) << "pixels more than one step apart";
}

// lights.shade: deferred on llvmpipe, "auto" shades on the CPU and says so; the picture is the
// GL-shaded one to one 8-bit step. "cpu" asked for with the forward pipeline: exit 2, the key.
TEST_F(LightsCli, RenderShadedOnTheCpuIsTheGlShadedPicture) {
  const std::string deferred = " --set lights.pipeline=deferred";
  const auto cpu = runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ +
                               "/shade_cpu" + deferred);
  ASSERT_EQ(cpu.exitCode, 0) << cpu.output;
  EXPECT_NE(cpu.output.find("shaded on the CPU"), std::string::npos) << cpu.output;
  const auto gl = runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ +
                              "/shade_gl" + deferred + " --set lights.shade=gl");
  ASSERT_EQ(gl.exitCode, 0) << gl.output;
  EXPECT_EQ(gl.output.find("shaded on the CPU"), std::string::npos) << gl.output;
  const auto a = pixels(dir_ + "/shade_cpu/fireflies_quad_00001.png");
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(differing(a, pixels(dir_ + "/shade_gl/fireflies_quad_00001.png")), 0.0);
  const auto bad = runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ +
                               "/shade_bad --set lights.shade=cpu");
  EXPECT_EQ(bad.exitCode, 2) << bad.output;
  EXPECT_NE(bad.output.find("lights.shade"), std::string::npos) << bad.output;
}

// lights.cull (on by default): `render` says it culls, and draws the picture of the whole
// volume byte for byte - from the scene's camera (the water's quad splats in view) and from a
// close one on the cup that sees a small part of the tank.
TEST_F(LightsCli, RenderCulledIsTheUnculledPicture) {
  const std::string cup =
      " --set camera.position=[0.62,0.3,0.05] --set camera.target=[0.35,0.07,-0.25]";
  for (const std::string& camera : {std::string(), cup}) {
    const std::string name = camera.empty() ? "scene" : "cup";
    const auto culled = runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ +
                                    "/culled_" + name + camera);
    ASSERT_EQ(culled.exitCode, 0) << culled.output;
    EXPECT_NE(culled.output.find("culled to the view"), std::string::npos) << culled.output;
    const auto all = runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ + "/all_" +
                                 name + camera + " --set lights.cull=false");
    ASSERT_EQ(all.exitCode, 0) << all.output;
    EXPECT_EQ(all.output.find("culled to the view"), std::string::npos) << all.output;
    const auto a = pixels(dir_ + "/all_" + name + "/fireflies_quad_00001.png");
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == pixels(dir_ + "/culled_" + name + "/fireflies_quad_00001.png")) << name;
  }
}

// The viewer lights the frame the same way (a window under Xvfb, its screenshot).
TEST_F(LightsCli, ViewerShowsTheLitFrame) {
  if (std::system("command -v xvfb-run > /dev/null") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const std::string shot = dir_ + "/view_lights.png";
  const std::string command = "xvfb-run -a -s '-screen 0 800x600x24' " + test::sphsplatCommand() +
                              " view " + dir_ + "/ff.h5 --frame last --width 200 --height 150" +
                              " --exit-after 2 --screenshot " + shot + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  int w = 0, h = 0;
  const auto rgb = io::exports::readPng(shot, w, h);
  int warm = 0;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3)
    warm += rgb[i] > 90 && rgb[i] > rgb[i + 2] + 30;
  EXPECT_GT(warm, 20) << "pixels lit by the fireflies";
  // The viewer culls the volume to the scene's camera (lights.cull, on): the same picture as the
  // whole volume's, byte for byte - in a window twice as wide as high, wider than the scene's
  // 4:3 render section, so a volume culled for the render section's picture would miss lights
  // at the sides.
  auto viewShot = [&](const std::string& name, const std::string& keys) {
    const std::string png = dir_ + "/" + name + ".png";
    const std::string line = "xvfb-run -a -s '-screen 0 800x600x24' " + test::sphsplatCommand() +
                             " view " + dir_ + "/ff.h5 --frame last --width 300 --height 150" +
                             keys + " --exit-after 2 --screenshot " + png + " > /dev/null 2>&1";
    EXPECT_EQ(std::system(line.c_str()), 0) << line;
    return pixels(png);
  };
  // From close to the cup, which sees a small part of the tank (RenderCulledIsTheUnculledPicture).
  const std::string cup =
      " --set camera.position=[0.62,0.3,0.05] --set camera.target=[0.35,0.07,-0.25]";
  const std::vector<int> culled = viewShot("view_wide_culled", cup);
  const std::vector<int> all = viewShot("view_wide_whole", cup + " --set lights.cull=false");
  // Below the HUD (its top rows hold the frame's draw time, which differs between any two runs).
  const std::size_t belowHud = 80 * 300 * 3;
  ASSERT_EQ(culled.size(), all.size());
  ASSERT_GT(culled.size(), belowHud);
  EXPECT_TRUE(std::equal(culled.begin() + belowHud, culled.end(), all.begin() + belowHud))
      << "culling changed the viewer's picture";
  // The deferred pipeline in the window: the same picture (the lighting pass writes the depth the
  // window's own depth buffer tests the later layers against).
  const std::string deferred = dir_ + "/view_lights_deferred.png";
  const std::string again = "xvfb-run -a -s '-screen 0 800x600x24' " + test::sphsplatCommand() +
                            " view " + dir_ + "/ff.h5 --frame last --width 200 --height 150" +
                            " --set lights.pipeline=deferred --exit-after 2 --screenshot " +
                            deferred + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(again.c_str()), 0) << again;
  EXPECT_LT(differing(pixels(shot), pixels(deferred)), 0.02);
}

// No `lights` section: no volume, no line about it (the dam break has none).
TEST_F(LightsCli, ASceneWithoutLightsHasNoLightVolume) {
  const std::string dam = dir_ + "/dam.h5";
  ASSERT_EQ(runSphsplat("run " + test::sourcePath("scenes/dam_break.json") +
                        " --set solver.spacing=0.02 --end 0.05 -q --output " + dam)
                .exitCode,
            0);
  const auto r =
      runSphsplat("render " + dam + " --frames last --size 64x48 --out " + dir_ + "/dam");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("particle lights"), std::string::npos) << r.output;
  const auto c = runSphsplat("compare " + dam + " --size 64x48 --out " + dir_ + "/dam");
  EXPECT_EQ(c.output.find("particle lights"), std::string::npos) << c.output;
}

TEST_F(LightsCli, BadLightsKeysAreOneLineAndExitTwo) {
  for (const std::string& set :
       {std::string("lights.filter=cubic"), std::string("lights.volume.voxels=512"),
        std::string("lights.accumulate=racy"), std::string("lights.source=rain"),
        std::string("lights.cull=maybe")}) {
    const auto r =
        runSphsplat("render " + dir_ + "/ff.h5 --frames last --out " + dir_ + "/bad --set " + set);
    EXPECT_EQ(r.exitCode, 2) << set << ": " << r.output;
    EXPECT_NE(r.output.find(set.substr(0, set.find('='))), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
}

}  // namespace
}  // namespace sph
