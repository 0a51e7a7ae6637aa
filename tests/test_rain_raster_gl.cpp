// The rain's CPU streak rasteriser (rain.draw "cpu") against the GL triangles of rain.draw
// "triangles" on llvmpipe: the same pixels within rounding and the same fragment count, and for
// either drops behind a solid hidden by the depth test while those in front of it show.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "render/gl/GlContext.h"
#include "render/gl/GlHandle.h"
#include "render/rain/RainRenderer.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/rain/RainSystem.h"
#include "sim/scene/Camera.h"
#include "tests/RainRasterScenes.h"

namespace sph::render::rain {
namespace {

using test::streaks::camera;
using test::streaks::desc;
using test::streaks::kAspect;
using test::streaks::kHeight;
using test::streaks::kWidth;

class RainRasterGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

// The frame of `d`'s drops (none: count 0) over a light sky, with `solids` (may be empty), and
// the fragments the rain drew (GL's count for the triangles, the rasteriser's for "cpu").
struct Frame {
  frame::RenderImage image;
  std::uint64_t fragments = 0;
};
Frame drawFrame(const scene::RainDesc& d, const std::vector<scene::BoundaryShape>& solids) {
  sph::rain::RainSystem drops(d, kAspect);
  drops.reset(camera());
  RainRenderer layer(d);
  layer.setDrops(drops);
  splat::SplatRenderer r(kWidth, kHeight);
  std::unique_ptr<solids::SolidRenderer> solid;
  std::vector<frame::FrameLayer*> layers;
  if (!solids.empty()) {
    solid = std::make_unique<solids::SolidRenderer>(solids, Aabb{Vec3(-9, -9, -9), Vec3(9, 9, 9)},
                                                    0.01f);
    layers.push_back(solid.get());
  }
  if (d.count > 0) layers.push_back(&layer);
  r.setLayers(layers);
  Frame f;
  auto query = gl::Query::create(GL_SAMPLES_PASSED);
  if (!layer.raster()) glBeginQuery(GL_SAMPLES_PASSED, query.id());
  f.image = r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera(), frame::Lighting{});
  if (layer.raster()) {
    f.fragments = layer.raster()->fragments();
  } else {
    glEndQuery(GL_SAMPLES_PASSED);
    GLuint64 n = 0;
    glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &n);
    f.fragments = n;
  }
  return f;
}

// The CPU path against the triangles on the same drops: the pixels GL fills are those whose
// centre is in the quad, which the rasteriser reproduces; what differs is rounding (GL rounds the
// RGBA8 frame after each blend, the rasteriser once; its bilinear weights are 8-bit) and the
// rare pixel centre on a quad's edge.
TEST_F(RainRasterGl, TheCpuPathDrawsTheTrianglesPictureWithinRounding) {
  const Frame cpu = drawFrame(desc(3000, scene::RainDraw::Cpu), {});
  const Frame triangles = drawFrame(desc(3000, scene::RainDraw::Triangles), {});
  const Frame sky = drawFrame(desc(0, scene::RainDraw::Triangles), {});
  double squared = 0;
  int worst = 0, over8 = 0, streakPixels = 0;
  for (std::size_t i = 0; i < cpu.image.rgb.size(); ++i) {
    const int diff = std::abs(int(cpu.image.rgb[i]) - int(triangles.image.rgb[i]));
    squared += diff * diff;
    worst = std::max(worst, diff);
    over8 += diff > 8;
    streakPixels += triangles.image.rgb[i] != sky.image.rgb[i];
  }
  const double mse = squared / static_cast<double>(cpu.image.rgb.size());
  const double psnr = 10 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
  std::printf(
      "fragments cpu %llu, triangles %llu; PSNR %.1f dB, worst %d, %d of %d values "
      "off by > 8 (%d values show rain)\n",
      static_cast<unsigned long long>(cpu.fragments),
      static_cast<unsigned long long>(triangles.fragments), psnr, worst, over8,
      static_cast<int>(cpu.image.rgb.size()), streakPixels);
  EXPECT_GT(streakPixels, 5000);  // the rain is there to compare
  EXPECT_NEAR(static_cast<double>(cpu.fragments), static_cast<double>(triangles.fragments),
              0.01 * static_cast<double>(triangles.fragments));
  EXPECT_GT(psnr, 45.0);
  EXPECT_LT(over8, streakPixels / 200);
}

// A wall over the left half of the picture, between the camera and the rain: the drops behind
// it leave its pixels exactly as they were and show beside it; drops in front of it show on it.
class RainBehindASolid : public ::testing::TestWithParam<scene::RainDraw> {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};
INSTANTIATE_TEST_SUITE_P(Draw, RainBehindASolid,
                         ::testing::Values(scene::RainDraw::Cpu, scene::RainDraw::Triangles),
                         [](const auto& p) { return std::string(nameOf(p.param)); });

TEST_P(RainBehindASolid, IsHiddenWhereTheSolidIsAndShowsBesideIt) {
  scene::BoundaryShape wall;
  wall.kind = scene::BoundaryShape::Kind::Block;
  wall.lo = Vec3(-5, -5, 1.9f), wall.hi = Vec3(0, 5, 2);
  auto rain = [&](float zLo, float zHi) {
    scene::RainDesc d = desc(4000, GetParam());
    d.spotlight.reset();
    d.spawn = scene::RainSpawn::Region;
    d.region.lo = Vec3(-2, -0.5f, zLo), d.region.hi = Vec3(2, 2.5f, zHi);
    return d;
  };
  const frame::RenderImage solidOnly = drawFrame(desc(0, GetParam()), {wall}).image;
  const frame::RenderImage sky = drawFrame(desc(0, GetParam()), {}).image;
  const frame::RenderImage behind = drawFrame(rain(0, 1.5f), {wall}).image;
  const frame::RenderImage inFront = drawFrame(rain(2.3f, 3), {wall}).image;
  int wallPixels = 0, changedOnWall = 0, changedBeside = 0, inFrontOnWall = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(kWidth) * kHeight; ++p) {
    bool onWall = false, b = false, f = false;
    for (int k = 0; k < 3; ++k) {
      onWall = onWall || solidOnly.rgb[3 * p + k] != sky.rgb[3 * p + k];
      b = b || behind.rgb[3 * p + k] != solidOnly.rgb[3 * p + k];
      f = f || inFront.rgb[3 * p + k] != solidOnly.rgb[3 * p + k];
    }
    wallPixels += onWall;
    changedOnWall += onWall && b;
    changedBeside += !onWall && b;
    inFrontOnWall += onWall && f;
  }
  std::printf(
      "wall %d pixels: rain behind changed %d of them and %d beside; rain in front "
      "changed %d on it\n",
      wallPixels, changedOnWall, changedBeside, inFrontOnWall);
  EXPECT_GT(wallPixels, kWidth * kHeight / 3);
  EXPECT_EQ(changedOnWall, 0);
  EXPECT_GT(changedBeside, 1000);
  EXPECT_GT(inFrontOnWall, 1000);
}

}  // namespace
}  // namespace sph::render::rain
