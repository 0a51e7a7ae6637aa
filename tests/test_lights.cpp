// render/lights: particles as lights (seed 004) in the drawn picture, on the real GL (llvmpipe).
// A light over a plane lights the drawn plane as the formula says, and the water's splats as
// well; the deferred pipeline gives the forward picture to one 8-bit step, also shaded on the CPU,
// where the copy keeps the background and the depth drawn against. The volume itself is
// test_lights_volume, its filters and the exact reference test_lights_filters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/lights/LightVolume.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/Camera.h"
#include "tests/LightTestScenes.h"
#include "tests/LightsGlTest.h"

namespace sph::render::lights {
namespace {

using test::light;
using test::LightsGl;

// The drawn picture: a plane seen from above, lit only by one particle light 0.3 m over a voxel
// centre (nearest filter): the pixel under the light is kd base att(0.3) (n.l = 1), the pixel
// under the neighbouring voxel centre 0.3 m aside kd base att(0.3 sqrt 2) cos 45.
TEST_F(LightsGl, ALightOverAPlaneLightsTheDrawnPlaneByTheFormula) {
  scene::LightsDesc d;
  d.origin = Vec3(-0.5f, -0.05f, -0.5f), d.voxelSize = 0.1f, d.voxels = {10, 10, 10};
  d.attenuation = {1.0f, 0.0f, 4.0f}, d.range = 0.5f, d.filter = scene::LightFilter::Nearest;
  d.specular = 0;
  LightVolume volume(d);
  const Vec3 lamp(0.05f, 0.3f, 0.05f);
  volume.update({light(lamp, Vec3::Ones(), 1.0f)});
  scene::BoundaryShape plane;
  plane.kind = scene::BoundaryShape::Kind::Plane;
  plane.point = Vec3::Zero(), plane.normal = Vec3::UnitY();
  solids::SolidRenderer solids({plane}, Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, 0.02f);
  solids.material.ambient = 0, solids.material.diffuse = 0, solids.material.specular = 0;
  solids.material.colour = Vec3(0.8f, 0.6f, 0.4f);
  const int size = 128;
  splat::SplatRenderer r(size, size);
  r.setLayers({&solids});
  scene::CameraDesc top;
  top.position = Vec3(0.05f, 2, 0.05f), top.target = Vec3(0.05f, 0, 0.05f), top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 30;
  frame::Lighting lighting;
  lighting.extra = &volume;
  const frame::RenderImage picture =
      r.render(splat::SplatFrame{}, splat::SplatKind::Point, top, lighting);
  const scene::CameraFrame cf = cameraFrame(top, 1.0f);
  auto pixel = [&](const Vec3& w) {
    float c[4];
    for (int row = 0; row < 4; ++row)
      c[row] = cf.projView(row, 0) * w.x() + cf.projView(row, 1) * w.y() +
               cf.projView(row, 2) * w.z() + cf.projView(row, 3);
    const int px = static_cast<int>((c[0] / c[3] + 1) * 0.5f * size);
    const int py = static_cast<int>((1 - c[1] / c[3]) * 0.5f * size);
    return static_cast<std::size_t>(py * size + px);
  };
  auto linear = [](std::uint8_t s8) {
    const float s = s8 / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
  };
  auto expectPixel = [&](const Vec3& w, float lightValue) {
    const std::size_t p = pixel(w);
    for (int a = 0; a < 3; ++a) {
      const float want = solids.material.colour[a] * lightValue;
      // One 8-bit sRGB step at that level, in linear terms.
      const float step =
          linear(static_cast<std::uint8_t>(std::min(255, picture.rgb[3 * p + a] + 1))) -
          linear(picture.rgb[3 * p + a]);
      EXPECT_NEAR(linear(picture.rgb[3 * p + a]), want, step + 2e-3f) << "channel " << a;
    }
  };
  expectPixel(Vec3(0.05f, 0, 0.05f), 1.0f / (1 + 4 * 0.09f));
  const float d45 = 0.3f * std::sqrt(2.0f);
  expectPixel(Vec3(0.35f, 0, 0.05f), std::sqrt(0.5f) / (1 + 4 * d45 * d45));
  expectPixel(Vec3(-0.45f, 0, -0.45f), 0.0f);  // out of range
}

// The water's splats take the same light as the solids. (Their programs without particle-light
// code are for scenes without `lights`; a lit scene must get the lit ones.)
TEST_F(LightsGl, WaterSplatsAreLitByTheVolumeToo) {
  scene::LightsDesc d;
  d.origin = Vec3(-0.5f, -0.05f, -0.5f), d.voxelSize = 0.1f, d.voxels = {10, 10, 10};
  d.attenuation = {1.0f, 0.0f, 4.0f}, d.range = 0.5f, d.filter = scene::LightFilter::Nearest;
  d.specular = 0;
  LightVolume volume(d);
  volume.update({light(Vec3(0.05f, 0.3f, 0.05f), Vec3::Ones(), 1.0f)});
  splat::SplatFrame frame;
  frame.halfSize = 0.05f;
  frame.points.push_back(splat::SplatVertex{{0.05f, 0, 0.05f}, {0, 1, 0}});  // facing the lamp
  const int size = 32;
  splat::SplatRenderer r(size, size);
  scene::CameraDesc top;
  top.position = Vec3(0.05f, 2, 0.05f), top.target = Vec3(0.05f, 0, 0.05f), top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 30;
  frame::Lighting unlit;  // no scene light at all: only the particle light can colour the splat
  unlit.ambient = 0, unlit.diffuse = 0, unlit.specular = 0, unlit.environment = false;
  unlit.base = Vec3(0.8f, 0.6f, 0.4f);
  frame::Lighting lit = unlit;
  lit.extra = &volume;
  const std::size_t centre = static_cast<std::size_t>(size / 2 * size + size / 2);
  const frame::RenderImage dark = r.render(frame, splat::SplatKind::Point, top, unlit);
  const frame::RenderImage bright = r.render(frame, splat::SplatKind::Point, top, lit);
  auto linear = [](std::uint8_t s8) {
    const float s = s8 / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
  };
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(dark.rgb[3 * centre + a], 0) << "channel " << a;
    // The nearest voxel's centre is 0.3 m under the lamp: 1 / (1 + 4 * 0.09), straight down.
    EXPECT_NEAR(linear(bright.rgb[3 * centre + a]), unlit.base[a] / (1 + 4 * 0.09f), 0.02f)
        << "channel " << a;
  }
}

// 24^3 voxels of 0.05 m over test::sheetSolids(), trilinear, forward.
scene::LightsDesc sheetVolume() {
  scene::LightsDesc d;
  d.origin = Vec3(-0.6f, -0.1f, -0.6f), d.voxelSize = 0.05f, d.voxels = {24, 24, 24};
  d.attenuation = {1.0f, 0.0f, 20.0f}, d.range = 0.3f, d.filter = scene::LightFilter::Trilinear;
  d.specular = 0.5f, d.shininess = 16, d.roomLight = 0.3f;
  return d;
}

// lights.pipeline "deferred" (seed 004 Fig. 11): a G-buffer of the solids and the opaque water,
// then one full-screen lighting pass, gives the forward image to one 8-bit step per channel -
// solids per pixel, point splats lit at their centre either way, translucent water composited
// forward on the deferred-lit frame, depth tested against it (splats half hidden by the sphere).
TEST_F(LightsGl, DeferredGivesTheForwardImageToOneStep) {
  scene::LightsDesc d = sheetVolume();
  const std::vector<sph::lights::LightParticle> lights = test::sheetLights(14);
  LightVolume forward(d);
  d.pipeline = scene::LightPipeline::Deferred;
  LightVolume deferred(d);
  ASSERT_FALSE(forward.deferred());
  ASSERT_TRUE(deferred.deferred());
  forward.update(lights), deferred.update(lights);
  solids::SolidRenderer solids(test::sheetSolids(), Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, 0.02f);
  const splat::SplatFrame water = test::waterSheet();  // partly behind the sphere
  const int width = 160, height = 120;
  splat::SplatRenderer r(width, height);
  r.setLayers({&solids});
  const scene::CameraDesc camera = test::sheetCamera();
  for (float alpha : {1.0f, 0.5f}) {
    frame::Lighting lighting;
    lighting.alpha = alpha;
    lighting.extra = &forward;
    const frame::RenderImage f = r.render(water, splat::SplatKind::Point, camera, lighting);
    EXPECT_EQ(r.lastPasses().lighting, 0.0);
    lighting.extra = &deferred;
    const frame::RenderImage g = r.render(water, splat::SplatKind::Point, camera, lighting);
    EXPECT_GT(r.lastPasses().lighting, 0.0) << "the lighting pass ran";
    lighting.extra = nullptr;
    const frame::RenderImage unlit = r.render(water, splat::SplatKind::Point, camera, lighting);
    const test::Steps diff = test::steps(f, g, unlit);
    EXPECT_LE(diff.worst, 1) << "alpha " << alpha;
    // The error figures' normal target: the water's coverage and normals, as forward draws them.
    lighting.extra = &forward;
    const frame::RenderImage fs = r.render(water, splat::SplatKind::Point, camera, lighting,
                                           frame::ImageContents::ColourAndNormals);
    lighting.extra = &deferred;
    const frame::RenderImage gs = r.render(water, splat::SplatKind::Point, camera, lighting,
                                           frame::ImageContents::ColourAndNormals);
    EXPECT_EQ(fs.covered, gs.covered) << "alpha " << alpha;
    float normalDiff = 0;
    for (std::size_t i = 0; i < fs.normal.size(); ++i)
      normalDiff = std::max(normalDiff, std::abs(fs.normal[i] - gs.normal[i]));
    EXPECT_LT(normalDiff, 1e-3f) << "alpha " << alpha;
    // Not two dark pictures: the particle lights (and the room light) change much of the frame.
    EXPECT_GT(diff.lit, width * height / 4) << "alpha " << alpha;
  }
}

// Shaded on the CPU (lights.shade "cpu"), the deferred frame reaches the target by a blit where
// nothing drawn after it is depth tested against it: the pixels without a surface keep the
// background, and the picture is the forward one to one step. Where the walls' points follow
// (depth tested, as forward draws them), the lighting pass restores the depth instead: a point
// behind the sphere stays hidden, one in front of it shows.
TEST_F(LightsGl, ShadedOnTheCpuTheCopyKeepsTheBackgroundAndTheDepthThatIsDrawnAgainst) {
  scene::LightsDesc d = sheetVolume();
  const std::vector<sph::lights::LightParticle> lights = test::sheetLights(14);
  LightVolume forward(d);
  d.pipeline = scene::LightPipeline::Deferred, d.accumulate = scene::LightAccumulate::Cpu;
  d.shade = scene::LightShade::Cpu;
  LightVolume cpu(d);
  ASSERT_TRUE(cpu.shadesOnCpu());
  forward.update(lights), cpu.update(lights);
  solids::SolidRenderer solids(test::sheetSolids(), Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, 0.02f);
  const int width = 160, height = 120;
  splat::SplatRenderer r(width, height);
  r.setLayers({&solids});
  const scene::CameraDesc camera = test::sheetCamera();
  frame::Lighting lighting;
  lighting.background = Vec3(0.3f, 0.5f, 0.7f);
  auto picture = [&](const LightVolume& v) {
    lighting.extra = &v;
    return r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
  };
  const frame::RenderImage f = picture(forward), g = picture(cpu);
  lighting.extra = nullptr;
  const frame::RenderImage unlit =
      r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
  const test::Steps diff = test::steps(f, g, unlit);
  EXPECT_LE(diff.worst, 1);
  EXPECT_GT(diff.lit, width * height / 4);
  std::size_t background = 0;
  for (std::size_t i = 0; i < g.rgb.size(); i += 3) {
    bool same = true;
    for (int k = 0; k < 3; ++k) same &= g.rgb[i + k] == frame::toSrgb8(lighting.background[k]);
    background += same;
  }
  EXPECT_GT(background, 500u) << "the sky beyond the floor";
  // A wall point 0.3 m behind the sphere's centre seen from the camera, and one 0.3 m before it.
  const Vec3 centre(0, 0.15f, 0), ray = (centre - camera.position).normalized();
  const Vec3 toCamera = -ray;
  auto withWall = [&](const Vec3& at) {
    r.setBoundary(
        {splat::SplatVertex{{at.x(), at.y(), at.z()}, {toCamera.x(), toCamera.y(), toCamera.z()}}},
        0.05f);
    const frame::RenderImage a = picture(forward), b = picture(cpu);
    EXPECT_LE(test::steps(a, b, a).worst, 1);
    return b;
  };
  const frame::RenderImage behind = withWall(centre + 0.3f * ray);
  const frame::RenderImage before = withWall(centre - 0.3f * ray);
  EXPECT_LE(test::steps(behind, g, g).worst, 1) << "hidden by the sphere";
  EXPECT_GE(test::steps(before, g, g).worst, 3) << "in front of it: the walls' grey shows";
}

}  // namespace
}  // namespace sph::render::lights
