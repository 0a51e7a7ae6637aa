// lights.shade "cpu" (render/lights/CpuShading.h): the particle lights' term computed on the CPU
// from the volume lights.accumulate "cpu" gathered is the GL term - at probe points through each
// filter it has, and in the deferred frame to one 8-bit step, culled or not, with translucent
// water drawn forward over it (which samples the 3D textures: uploaded then, and only then);
// "auto" picks it where the volume is on the CPU and the frame deferred, and "cpu" asked for
// where it cannot work is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "render/frame/Srgb8Table.h"
#include "render/gl/GlContext.h"
#include "render/lights/CpuShading.h"
#include "render/lights/LightCulling.h"
#include "render/lights/LightVolume.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/InputError.h"
#include "sim/scene/Camera.h"
#include "tests/LightTestScenes.h"

namespace sph::render::lights {
namespace {

using test::light;

class LightsShade : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

// 24^3 voxels of 0.05 m over a floor, a sphere and a block; deferred, accumulated on the CPU.
scene::LightsDesc scene(scene::LightShade shade) {
  scene::LightsDesc d;
  d.origin = Vec3(-0.6f, -0.1f, -0.6f), d.voxelSize = 0.05f, d.voxels = {24, 24, 24};
  d.attenuation = {1.0f, 0.0f, 20.0f}, d.range = 0.3f, d.filter = scene::LightFilter::Trilinear;
  d.specular = 0.5f, d.shininess = 16, d.roomLight = 0.3f;
  d.pipeline = scene::LightPipeline::Deferred, d.accumulate = scene::LightAccumulate::Cpu,
  d.shade = shade;
  return d;
}

TEST_F(LightsShade, TheCpuTermIsTheGlTermAtPointsThroughEachFilter) {
  LightVolume volume(scene(scene::LightShade::Cpu));
  ASSERT_TRUE(volume.shadesOnCpu());
  volume.update(test::sheetLights(3));
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<ProbePoint> points;
  for (int i = 0; i < 2000; ++i) {  // over the whole volume and a little beyond its faces
    ProbePoint p;
    p.position = Vec3(0.65f * u(rng), 0.5f + 0.65f * u(rng), 0.65f * u(rng));
    p.normal = Vec3(u(rng), u(rng) + 1.2f, u(rng)).normalized();
    p.toEye = Vec3(u(rng), 1.0f, u(rng)).normalized();
    points.push_back(p);
  }
  const Vec3 base(0.8f, 0.7f, 0.6f);
  for (scene::LightFilter f : {scene::LightFilter::Nearest, scene::LightFilter::Trilinear}) {
    for (int n : {1, 2}) {
      volume.setFilter(f, 0.0f, n);
      for (int terms : {1, 2, 3}) {
        volume.terms = terms;
        const std::vector<Vec3> gl = volume.probe(points, base);
        const std::vector<Vec3> cpu = volume.probeOnCpu(points, base);
        float worst = 0;
        int lit = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
          worst = std::max(worst, (gl[i] - cpu[i]).norm() / (1e-3f + gl[i].norm()));
          lit += gl[i].maxCoeff() > 0.01f;
        }
        // The same texels and float weights: rounding alone (8-bit weights: 3-66% off).
        EXPECT_LT(worst, 1e-3f) << nameOf(f) << " x" << n << " terms " << terms;
        EXPECT_GT(lit, 100) << nameOf(f) << " x" << n << " terms " << terms;
      }
    }
  }
  volume.terms = 3;
}

// The pixel loop (the filter's texels in SIMD registers, the Phong terms in SIMD lanes over a
// row's lit pixels, in blocks of 256 columns) computes each pixel's term as at() does at its
// position, bit for bit: every path rounds alike (CpuShading.h). Rows wider than a block, points
// inside the lights' box, on its faces and beyond the volume, pixels with nothing drawn.
TEST_F(LightsShade, ThePixelLoopShadesEachPixelAsTheTermAtItsPoint) {
  LightVolume volume(scene(scene::LightShade::Cpu));
  volume.update(test::sheetLights(3));
  const int width = 301, height = 3;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> depth(n), position(4 * n), normal(4 * n), lit(4 * n);
  std::vector<std::uint16_t> albedo(4 * n);
  const Vec3 base(0.75f, 0.5f, 0.25f), eye(0.3f, 1.2f, 0.9f);  // a base exact in half floats
  for (std::size_t i = 0; i < n; ++i) {
    depth[i] = u(rng) < -0.8f ? 1.0f : 0.5f;  // a tenth undrawn
    const Vec3 p(0.7f * u(rng), 0.5f + 0.7f * u(rng), 0.7f * u(rng));
    const Vec3 nn = Vec3(u(rng), u(rng) + 1.2f, u(rng)).normalized();
    for (int a = 0; a < 3; ++a) {
      position[4 * i + a] = p[a], normal[4 * i + a] = nn[a];
      albedo[4 * i + a] = toHalf(base[a]), lit[4 * i + a] = 0.2f * (u(rng) + 1.0f);
    }
  }
  frame::GBufferPixels g;
  g.width = width, g.height = height;
  g.depth = depth.data(), g.position = position.data(), g.normal = normal.data();
  g.albedo = albedo.data(), g.lit = lit.data();
  const frame::Srgb8Table& encode = frame::srgb8Table();
  std::vector<std::uint8_t> rgba(4 * n);
  for (scene::LightFilter f : {scene::LightFilter::Nearest, scene::LightFilter::Trilinear}) {
    for (int over : {1, 2}) {
      volume.setFilter(f, 0.0f, over);
      for (int terms : {1, 2, 3}) {
        volume.terms = terms;
        volume.shadeOnCpu(g, eye, rgba.data());
        std::vector<ProbePoint> points(n);
        for (std::size_t i = 0; i < n; ++i) {
          const Vec3 p(position[4 * i], position[4 * i + 1], position[4 * i + 2]);
          points[i] = {p, Vec3(normal[4 * i], normal[4 * i + 1], normal[4 * i + 2]),
                       CpuShading::toEye(eye, p)};
        }
        const std::vector<Vec3> term = volume.probeOnCpu(points, base);
        int differ = 0, changed = 0;  // bytes unlike at()'s; bytes the lights change
        for (std::size_t i = 0; i < n; ++i) {
          std::array<std::uint8_t, 4> want{0, 0, 0, 0};
          if (depth[i] < 1.0f) {
            for (int a = 0; a < 3; ++a) {
              want[static_cast<std::size_t>(a)] = encode(lit[4 * i + a] + term[i][a]);
              changed += want[static_cast<std::size_t>(a)] != encode(lit[4 * i + a]);
            }
            want[3] = 255;
          }
          for (std::size_t a = 0; a < 4; ++a) differ += rgba[4 * i + a] != want[a];
        }
        EXPECT_EQ(differ, 0) << nameOf(f) << " x" << over << " terms " << terms;
        EXPECT_GT(changed, 50) << nameOf(f) << " x" << over << " terms " << terms;
      }
    }
  }
  volume.terms = 3;
}

// The deferred frame of test_lights.cpp's forward-against-deferred test, shaded by GL and by the
// CPU, whole volume and culled to the camera, opaque and translucent water (the latter drawn
// forward over the frame: it samples the 3D textures, which "cpu" uploads only then).
TEST_F(LightsShade, ShadedOnTheCpuTheDeferredFrameIsTheGlOneToOneStep) {
  const std::vector<sph::lights::LightParticle> lights = test::sheetLights(14);
  solids::SolidRenderer solids(test::sheetSolids(), Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, 0.02f);
  const splat::SplatFrame water = test::waterSheet();
  const int width = 160, height = 120;
  splat::SplatRenderer r(width, height);
  r.setLayers({&solids});
  const scene::CameraDesc camera = test::sheetCamera();
  const LightView view = lightView(camera, static_cast<float>(width) / height, 1.5f, 2.5f, 0.05f);
  LightVolume gl(scene(scene::LightShade::Gl)), cpu(scene(scene::LightShade::Cpu));
  ASSERT_FALSE(gl.shadesOnCpu());
  for (const LightView* v : {static_cast<const LightView*>(nullptr), &view}) {
    gl.update(lights, v), cpu.update(lights, v);
    for (float alpha : {1.0f, 0.5f}) {
      frame::Lighting lighting;
      lighting.alpha = alpha;
      lighting.extra = &gl;
      const frame::RenderImage a = r.render(water, splat::SplatKind::Point, camera, lighting);
      EXPECT_EQ(r.lastPasses().particles, 0.0);
      lighting.extra = &cpu;
      const frame::RenderImage b = r.render(water, splat::SplatKind::Point, camera, lighting);
      EXPECT_GT(r.lastPasses().particles, 0.0) << "the CPU pass ran";
      lighting.extra = nullptr;
      const frame::RenderImage unlit = r.render(water, splat::SplatKind::Point, camera, lighting);
      const test::Steps diff = test::steps(a, b, unlit);
      EXPECT_LE(diff.worst, 1) << "alpha " << alpha << (v ? ", culled" : "");
      EXPECT_GT(diff.lit, width * height / 4) << "alpha " << alpha << (v ? ", culled" : "");
    }
  }
  // Lights that move: the next frame's term, not the last one's.
  const std::vector<sph::lights::LightParticle> moved = test::sheetLights(15);
  gl.update(moved), cpu.update(moved);
  frame::Lighting lighting;
  lighting.extra = &gl;
  const frame::RenderImage a =
      r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
  lighting.extra = &cpu;
  const frame::RenderImage b =
      r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
  EXPECT_LE(test::steps(a, b, a).worst, 1) << "moved lights";
}

// Shaded on the CPU, a frame uploads nothing until something samples the textures; what is read
// then is the frame's volume, as the GL-shaded volume holds it (a smaller box after a larger one
// included: the voxels left from the last upload read zero).
TEST_F(LightsShade, TheTexturesHoldTheFrameWhenReadThoughNotUploadedEachFrame) {
  LightVolume gl(scene(scene::LightShade::Gl)), cpu(scene(scene::LightShade::Cpu));
  std::vector<sph::lights::LightParticle> few = test::sheetLights(4);
  few.resize(8);
  for (const std::vector<sph::lights::LightParticle>& lights : {test::sheetLights(4), few}) {
    gl.update(lights), cpu.update(lights);
    EXPECT_EQ(cpu.readColour(), gl.readColour());
    EXPECT_EQ(cpu.readDirection(), gl.readDirection());
  }
}

TEST_F(LightsShade, AutoShadesOnTheCpuWhereTheVolumeIsOnItAndTheFrameDeferred) {
  EXPECT_TRUE(LightVolume(scene(scene::LightShade::Auto)).shadesOnCpu());
  scene::LightsDesc d = scene(scene::LightShade::Auto);
  d.pipeline = scene::LightPipeline::Forward;
  EXPECT_FALSE(LightVolume(d).shadesOnCpu()) << "forward: no G-buffer to shade";
  d = scene(scene::LightShade::Auto), d.accumulate = scene::LightAccumulate::Atomic;
  EXPECT_FALSE(LightVolume(d).shadesOnCpu()) << "the volume is on the GPU";
  d = scene(scene::LightShade::Auto), d.filter = scene::LightFilter::Tricubic;
  EXPECT_FALSE(LightVolume(d).shadesOnCpu()) << "tricubic stays on GL";
  // Asked for where it cannot work: refused (the scene loader says so with the key first).
  for (auto change : {+[](scene::LightsDesc& x) { x.pipeline = scene::LightPipeline::Forward; },
                      +[](scene::LightsDesc& x) { x.accumulate = scene::LightAccumulate::Paper; },
                      +[](scene::LightsDesc& x) { x.filter = scene::LightFilter::Tricubic; }}) {
    d = scene(scene::LightShade::Cpu);
    change(d);
    try {
      LightVolume v(d);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("lights.shade"), std::string::npos) << e.what();
    }
  }
  // compare's tricubic rows on a "cpu" volume: the GL path, as the lighting pass would take.
  LightVolume v(scene(scene::LightShade::Cpu));
  v.setFilter(scene::LightFilter::Tricubic, 0.0f, 1);
  EXPECT_FALSE(v.shadesOnCpu());
  v.setFilter(scene::LightFilter::Trilinear, 0.0f, 1);
  EXPECT_TRUE(v.shadesOnCpu());
}

}  // namespace
}  // namespace sph::render::lights
