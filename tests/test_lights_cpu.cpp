// lights.accumulate "cpu" (render/lights/CpuAccumulation.h): the volume the CPU gathers and
// uploads is the atomic compute shader's, texel for texel to half-float rounding - spread lights,
// a crowded voxel, lights on the volume's faces and outside it - and culled to a view it fills the
// same box and leaves every other voxel zero, also after a frame of the whole volume; its half
// floats round as llvmpipe's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "render/gl/GlContext.h"
#include "render/lights/CpuAccumulation.h"
#include "render/lights/LightCulling.h"
#include "render/lights/LightVolume.h"
#include "sim/scene/Camera.h"
#include "tests/LightTestScenes.h"

namespace sph::render::lights {
namespace {

using Texels = std::vector<std::array<float, 4>>;

using test::light;

// 40 x 12 x 32 voxels of 0.05 m (range 0.12 m: 5^3 voxels visited per light).
scene::LightsDesc volume(scene::LightAccumulate mode) {
  scene::LightsDesc d;
  d.origin = Vec3(-1.0f, -0.1f, -0.8f), d.voxelSize = 0.05f, d.voxels = {40, 12, 32};
  d.attenuation = {1.0f, 2.0f, 30.0f}, d.range = 0.12f, d.accumulate = mode;
  return d;
}

std::vector<sph::lights::LightParticle> someLights() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<sph::lights::LightParticle> lights;
  for (int i = 0; i < 3000; ++i)  // spread, a few beyond the volume's faces
    lights.push_back(light(Vec3(2.2f * u(rng) - 1.1f, 0.7f * u(rng) - 0.15f, 1.8f * u(rng) - 0.9f),
                           Vec3(u(rng), u(rng), u(rng)), 0.2f + u(rng)));
  for (int i = 0; i < 500; ++i)  // crowded into one voxel
    lights.push_back(
        light(Vec3(0.21f + 0.01f * u(rng), 0.11f, -0.3f), Vec3(1.0f, 0.5f, 0.25f), 1.0f));
  lights.push_back(light(Vec3(-1.0f, -0.1f, -0.8f), Vec3::Ones(), 1.0f));  // on the corner
  return lights;
}

// Half floats hold 11 significant bits; one light's rounding may tip a texel by one step.
void expectSame(const Texels& a, const Texels& b, const char* what) {
  ASSERT_EQ(a.size(), b.size());
  int tipped = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t c = 0; c < 4; ++c) {
      const float d = std::abs(a[i][c] - b[i][c]);
      ASSERT_LE(d, 1e-3f * std::max(1.0f, std::abs(a[i][c]))) << what << " texel " << i;
      tipped += d > 0;
    }
  EXPECT_LT(tipped, static_cast<int>(a.size()) / 100) << what;
}

// The half floats the CPU path uploads: toward zero, as llvmpipe converts; 65504 the largest.
TEST(CpuAccumulation, HalfFloatsRoundTowardZero) {
  EXPECT_EQ(toHalf(0.0f), 0x0000);
  EXPECT_EQ(toHalf(1.0f), 0x3c00);
  EXPECT_EQ(toHalf(-2.0f), 0xc000);
  EXPECT_EQ(toHalf(65504.0f), 0x7bff);
  EXPECT_EQ(toHalf(65535.0f), 0x7bff);
  EXPECT_EQ(toHalf(1e10f), 0x7bff);
  EXPECT_EQ(toHalf(std::ldexp(1.0f, -14)), 0x0400);  // the smallest normal
  EXPECT_EQ(toHalf(std::ldexp(1.0f, -24)), 0x0001);  // the smallest subnormal
  EXPECT_EQ(toHalf(1.0f + std::ldexp(1.0f, -10)), 0x3c01);
  EXPECT_EQ(toHalf(1.0f + 1.99f * std::ldexp(1.0f, -10)), 0x3c01);
  EXPECT_EQ(toHalf(-1.0f - 1.99f * std::ldexp(1.0f, -10)), 0xbc01);
}

// lights.shade "cpu" reads the sums back: every finite half is its float exactly (a few by hand,
// and each one converts back to itself).
TEST(CpuAccumulation, HalfFloatsReadBackExactly) {
  EXPECT_EQ(fromHalf(0x3c00), 1.0f);
  EXPECT_EQ(fromHalf(0xc000), -2.0f);
  EXPECT_EQ(fromHalf(0x7bff), 65504.0f);
  EXPECT_EQ(fromHalf(0x0001), std::ldexp(1.0f, -24));
  EXPECT_EQ(fromHalf(0x3c01), 1.0f + std::ldexp(1.0f, -10));
  for (std::uint32_t h = 0; h < 0x10000; ++h) {
    if ((h & 0x7c00) == 0x7c00) continue;  // infinities and NaNs: never in a sum
    ASSERT_EQ(toHalf(fromHalf(static_cast<std::uint16_t>(h))), h) << std::hex << h;
  }
}

class LightsCpuGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

TEST_F(LightsCpuGl, TheCpuVolumeIsTheAtomicOne) {
  const std::vector<sph::lights::LightParticle> lights = someLights();
  LightVolume atomic(volume(scene::LightAccumulate::Atomic)),
      onCpu(volume(scene::LightAccumulate::Cpu));
  atomic.update(lights), onCpu.update(lights);
  const Texels colour = atomic.readColour();
  float brightest = 0;
  for (const auto& t : colour) brightest = std::max(brightest, t[0]);
  EXPECT_GT(brightest, 400.0f) << "the crowded voxel";
  expectSame(colour, onCpu.readColour(), "colour");
  expectSame(atomic.readDirection(), onCpu.readDirection(), "direction");
}

TEST_F(LightsCpuGl, AutoIsCpuInSoftwareAndGivesTheAtomicVolume) {
  const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const scene::LightAccumulate expected = renderer.find("llvmpipe") != std::string::npos
                                              ? scene::LightAccumulate::Cpu
                                              : scene::LightAccumulate::Atomic;
  const std::vector<sph::lights::LightParticle> lights = someLights();
  LightVolume automatic(volume(scene::LightAccumulate::Auto)),
      atomic(volume(scene::LightAccumulate::Atomic));
  EXPECT_EQ(automatic.desc().accumulate, expected) << renderer;
  automatic.update(lights), atomic.update(lights);
  expectSame(atomic.readColour(), automatic.readColour(), "colour");
  expectSame(atomic.readDirection(), automatic.readDirection(), "direction");
}

TEST_F(LightsCpuGl, CulledToAViewItFillsTheSameBox) {
  const std::vector<sph::lights::LightParticle> lights = someLights();
  scene::CameraDesc camera;
  camera.position = Vec3(0.2f, 0.35f, -0.1f), camera.target = Vec3(0.2f, 0.0f, -0.3f);
  camera.fovYDegrees = 30, camera.near = 0.05f, camera.far = 10;
  const LightView view = lightView(camera, 4.0f / 3.0f, 1.5f, 2.5f, 0.01f);
  LightVolume atomic(volume(scene::LightAccumulate::Atomic)),
      onCpu(volume(scene::LightAccumulate::Cpu));
  onCpu.update(lights);  // a whole volume first: its voxels outside the box must go
  atomic.update(lights, &view), onCpu.update(lights, &view);
  ASSERT_LT(onCpu.lastBox().count(), volume(scene::LightAccumulate::Cpu).voxelCount() / 2);
  EXPECT_EQ(onCpu.lastLights(), atomic.lastLights());
  expectSame(atomic.readColour(), onCpu.readColour(), "colour");
  expectSame(atomic.readDirection(), onCpu.readDirection(), "direction");
}

// The count pass tests 16 lights at a time in SIMD lanes and the rest one at a time (AVX-512
// builds): the same lights in another order give the same sums bit for bit (integer sums do not
// depend on the order), the same box and the same number kept, lights nudged across a cull
// plane's margin and on voxel faces and range shells included. A wrong lane, plane or axis in the
// vector code shows here; that its rounding is the scalar code's rests on the Fig. 11 lights'
// sums, the same bits as before it (docs/notes/2026-11-27-lights-fig11.md, "Fig. 11's CPU side
// vectorised").
TEST(CpuAccumulation, TheSumsDoNotDependOnTheLightsOrder) {
  const scene::LightsDesc d = volume(scene::LightAccumulate::Cpu);
  std::vector<sph::lights::LightParticle> lights = someLights();
  scene::CameraDesc camera;
  camera.position = Vec3(0.2f, 0.35f, -0.1f), camera.target = Vec3(0.2f, 0.0f, -0.3f);
  camera.fovYDegrees = 30, camera.near = 0.05f, camera.far = 10;
  const LightView view = lightView(camera, 4.0f / 3.0f, 1.5f, 2.5f, 0.01f);
  const VoxelBox box = viewVoxels(d, view);
  const ViewCull cull(d, view, box);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.1f, 0.1f);
  for (const Eigen::Vector4f& q : cull.frustum().planes)
    for (int k = 0; k < 64; ++k) {  // near the target, moved onto the plane's margin, nudged
      const Vec3 s = camera.target + Vec3(u(rng), u(rng), u(rng)), n = q.head<3>();
      const Vec3 onMargin = s - (n.dot(s) + q.w() + cull.reach()) * n;
      for (int step = -4; step <= 4; ++step)
        lights.push_back(light(onMargin + 3e-8f * static_cast<float>(step) * n, Vec3::Ones(), 1));
    }
  for (int i = 0; i < 400; ++i)  // quarter-voxel lattice: faces, centres, range shells
    lights.push_back(
        light(d.origin +
                  0.25f * d.voxelSize *
                      Vec3(static_cast<float>(i % 13 + 40), static_cast<float>(i % 7 + 8),
                           static_cast<float>(i % 11 + 30)) +
                  Vec3::Constant(d.range * static_cast<float>(i % 3 - 1)),
              Vec3(0.5f, 1.0f, 0.25f), 0.7f));
  ASSERT_NE(lights.size() % 16, 0u);
  for (const ViewCull* c : {static_cast<const ViewCull*>(nullptr), &cull}) {
    const VoxelBox b = c ? box : wholeVolume(d);
    VoxelSums given;
    accumulateOnCpu(d, lights, b, fixedScale(d), c, given);
    std::vector<sph::lights::LightParticle> other = lights;
    for (int order = 0; order < 2; ++order) {
      if (order == 0) std::rotate(other.begin(), other.begin() + 7, other.end());
      if (order == 1) std::reverse(other.begin(), other.end());
      VoxelSums sums;
      accumulateOnCpu(d, other, b, fixedScale(d), c, sums);
      EXPECT_EQ(sums.lights, given.lights) << (c ? "culled" : "whole") << ", order " << order;
      EXPECT_EQ(sums.touched.lo, given.touched.lo) << (c ? "culled" : "whole");
      EXPECT_EQ(sums.touched.hi, given.touched.hi) << (c ? "culled" : "whole");
      EXPECT_TRUE(sums.colour == given.colour) << (c ? "culled" : "whole") << ", order " << order;
      EXPECT_TRUE(sums.direction == given.direction) << (c ? "culled" : "whole");
    }
    if (c) {
      EXPECT_LT(given.lights, lights.size()) << "the cull keeps some, not all";
    }
  }
}

// Lights shorter than a voxel (range 0.4 voxel; Fig. 11's is 0.5), binned with 16-bit voxel
// ranges: one light near each of 600 voxel centres, in a random direction, a ten-thousandth of
// the range inside it or outside it, or half a range outside. Each inside one lights its voxel,
// as the atomic shader's, and nothing else is lit.
TEST_F(LightsCpuGl, LightsShorterThanAVoxelLightOnlyTheCentresInRange) {
  scene::LightsDesc d = volume(scene::LightAccumulate::Atomic);
  d.range = 0.02f;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> voxel(0, 1 << 20);
  std::normal_distribution<float> g(0.0f, 1.0f);
  const float distances[] = {0.9999f, 1.0001f, 1.5f};
  std::vector<sph::lights::LightParticle> lights;
  std::vector<bool> used(d.voxelCount(), false);
  std::size_t inside = 0;
  while (lights.size() < 600) {
    const std::array<int, 3> v{voxel(rng) % d.voxels[0], voxel(rng) % d.voxels[1],
                               voxel(rng) % d.voxels[2]};
    const std::size_t at =
        static_cast<std::size_t>((v[2] * d.voxels[1] + v[1]) * d.voxels[0] + v[0]);
    if (used[at]) continue;
    used[at] = true;
    const Vec3 centre =
        d.origin + d.voxelSize * (Vec3(static_cast<float>(v[0]), static_cast<float>(v[1]),
                                       static_cast<float>(v[2])) +
                                  Vec3::Constant(0.5f));
    const float k = distances[lights.size() % 3];
    inside += k < 1;
    lights.push_back(light(centre + k * d.range * Vec3(g(rng), g(rng), g(rng)).normalized(),
                           Vec3::Ones(), 1.0f));
  }
  LightVolume atomic(d);
  d.accumulate = scene::LightAccumulate::Cpu;
  LightVolume onCpu(d);
  atomic.update(lights), onCpu.update(lights);
  const Texels colour = onCpu.readColour();
  std::size_t lit = 0;
  for (const auto& t : colour) lit += t[0] > 0;
  EXPECT_EQ(lit, inside);
  expectSame(atomic.readColour(), colour, "colour");
  expectSame(atomic.readDirection(), onCpu.readDirection(), "direction");
}

// Only the voxels a frame's lights reach are uploaded: lights that move between frames (spread,
// then a cluster in one corner, then none) leave nothing of the last frame behind.
TEST_F(LightsCpuGl, MovingLightsLeaveNoStaleVoxels) {
  const std::vector<sph::lights::LightParticle> spread = someLights();
  std::vector<sph::lights::LightParticle> corner;
  for (int i = 0; i < 20; ++i)
    corner.push_back(light(Vec3(0.8f + 0.005f * i, 0.4f, 0.6f - 0.004f * i), Vec3::Ones(), 1.0f));
  LightVolume moving(volume(scene::LightAccumulate::Cpu)),
      fresh(volume(scene::LightAccumulate::Cpu));
  moving.update(spread);
  moving.update(corner);
  fresh.update(corner);
  const Texels colour = moving.readColour();
  std::size_t lit = 0;
  for (const auto& t : colour) lit += t[0] > 0;
  EXPECT_GT(lit, 20u);
  EXPECT_LT(lit, colour.size() / 100) << "the corner's voxels only";
  EXPECT_TRUE(colour == fresh.readColour());
  EXPECT_TRUE(moving.readDirection() == fresh.readDirection());
  moving.update({});
  for (const auto& t : moving.readColour()) ASSERT_EQ(t[0], 0.0f);
}

// The other way: a frame whose box holds the last frame's (the corner, then lights spread over
// it) takes the branch that clears nothing, since every voxel of its box is written again.
TEST_F(LightsCpuGl, LightsSpreadingOverTheLastFramesBoxRewriteIt) {
  const std::vector<sph::lights::LightParticle> spread = someLights();
  std::vector<sph::lights::LightParticle> corner;
  for (int i = 0; i < 20; ++i)
    corner.push_back(light(Vec3(0.8f + 0.005f * i, 0.4f, 0.6f - 0.004f * i), Vec3::Ones(), 5.0f));
  // The box of the voxels a frame lights (what it writes), from the volume read back.
  auto litBox = [](const Texels& texels) {
    const std::array<int, 3> n = volume(scene::LightAccumulate::Cpu).voxels;
    std::array<int, 3> lo = n, hi{-1, -1, -1};
    for (std::size_t i = 0; i < texels.size(); ++i) {
      if (texels[i][0] <= 0) continue;
      const int at[3] = {static_cast<int>(i % n[0]), static_cast<int>(i / n[0] % n[1]),
                         static_cast<int>(i / (n[0] * n[1]))};
      for (std::size_t a = 0; a < 3; ++a)
        lo[a] = std::min(lo[a], at[a]), hi[a] = std::max(hi[a], at[a]);
    }
    return std::make_pair(lo, hi);
  };
  LightVolume growing(volume(scene::LightAccumulate::Cpu)),
      fresh(volume(scene::LightAccumulate::Cpu));
  growing.update(corner);
  const auto first = litBox(growing.readColour());
  growing.update(spread);
  fresh.update(spread);
  const auto second = litBox(fresh.readColour());
  for (std::size_t a = 0; a < 3; ++a) {
    ASSERT_LT(second.first[a], first.first[a]) << "the spread lights' box must hold the corner's";
    ASSERT_GE(second.second[a], first.second[a]) << "the spread lights' box must hold the corner's";
  }
  EXPECT_TRUE(growing.readColour() == fresh.readColour());
  EXPECT_TRUE(growing.readDirection() == fresh.readDirection());
}

}  // namespace
}  // namespace sph::render::lights
