// The GL splat renderer on a real context (llvmpipe in CI): it draws what the CPU built, shades
// as render/frame/Lighting.h says, and the quad splats score against the reference ray-marcher.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "render/gl/GlContext.h"
#include "render/splat/ReferenceRaymarcher.h"
#include "render/splat/SplatBuilder.h"
#include "render/splat/SplatRenderer.h"
#include "tests/LatticeBlock.h"

namespace sph::render::splat {
namespace {

using test::Block;

class SplatGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

scene::CameraDesc topView() {
  scene::CameraDesc top;
  top.position = Vec3(0.05f, 0.6f, 0.05f);
  top.target = Vec3(0.05f, 0.0f, 0.05f);
  top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 20;
  return top;
}

TEST_F(SplatGl, ShadersLightASplatExactlyAsTheLightingModel) {
  // One splat facing up under a top camera, each renderer: the GLSL shadeSurface() and the C++
  // shade() must give the same 8-bit colour (the reference ray-marcher uses shade()).
  SplatRenderer r(8, 8);
  scene::CameraDesc top = topView();
  top.position = Vec3(0, 1, 0), top.target = Vec3::Zero();
  SplatFrame point;
  point.halfSize = 1.0f;
  point.points.push_back(SplatVertex{{0, 0, 0}, {0, 1, 0}});
  SplatFrame quad;
  quad.halfSize = 1.0f;
  quad.quads = {SplatVertex{{0, 0, 0}, {0, 1, 0}}, SplatVertex{{1, 0, 0}, {0, 1, 0}},
                SplatVertex{{0, 0, 1}, {0, 1, 0}}, SplatVertex{{-1, 0, 0}, {0, 1, 0}},
                SplatVertex{{0, 0, -1}, {0, 1, 0}}};
  quad.indices = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};
  for (bool environment : {false, true}) {
    frame::Lighting light;
    light.environment = environment;
    const Vec3 expected = frame::shade(light, Vec3::UnitY(), Vec3::UnitY());
    for (SplatKind kind : {SplatKind::Point, SplatKind::Quad}) {
      const frame::RenderImage img = r.render(kind == SplatKind::Point ? point : quad, kind, top,
                                              light, frame::ImageContents::ColourAndNormals);
      const std::size_t centre = 4 * 8 + 4;
      ASSERT_TRUE(img.covered[centre]);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(img.rgb[3 * centre + k], frame::toSrgb8(expected[k]), 1);
      EXPECT_NEAR(img.normal[3 * centre + 1], 1.0f, 1e-5f);
    }
  }
}

TEST_F(SplatGl, TranslucentWaterShowsItsBackLitFromTheSideTheEyeSees) {
  // Through translucent water the eye sees the far surface from inside, the side whose normal
  // points away. Lit with that normal a splat read as grazing (Fresnel 1: pure sky colour), the
  // white shards on the pour's jet; lit from the side seen it matches a splat that faces the eye.
  // Opaque water keeps the normal as it is (culling handles the back).
  SplatRenderer r(8, 8);
  scene::CameraDesc top = topView();
  top.position = Vec3(0, 1, 0), top.target = Vec3::Zero();
  auto splat = [](float ny) {
    SplatFrame point;
    point.halfSize = 1.0f;
    point.points.push_back(SplatVertex{{0, 0, 0}, {0, ny, 0}});
    return point;
  };
  const std::size_t centre = 4 * 8 + 4;
  frame::Lighting translucent;
  translucent.alpha = 0.5f;
  const frame::RenderImage facing = r.render(splat(1), SplatKind::Point, top, translucent);
  const frame::RenderImage away = r.render(splat(-1), SplatKind::Point, top, translucent);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(away.rgb[3 * centre + k], facing.rgb[3 * centre + k], 1) << "channel " << k;
  // Opaque: the away-facing splat is shaded with its own normal (grazing, the sky colour).
  const frame::Lighting opaque;
  const frame::RenderImage opaqueAway = r.render(splat(-1), SplatKind::Point, top, opaque);
  const Vec3 grazing = frame::shade(opaque, -Vec3::UnitY(), Vec3::UnitY());
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(opaqueAway.rgb[3 * centre + k], frame::toSrgb8(grazing[k]), 1);
  EXPECT_GT(std::abs(int(opaqueAway.rgb[3 * centre]) - int(facing.rgb[3 * centre])) +
                std::abs(int(opaqueAway.rgb[3 * centre + 2]) - int(facing.rgb[3 * centre + 2])),
            10);
}

TEST_F(SplatGl, BlockSeenFromAboveScoresAgainstTheReference) {
  const float dx = 0.01f;
  const Block b(12, 12, 12, dx);
  const DensityField f(b.x.data(), b.y.data(), b.z.data(), b.x.size(), dx, 2.5f);
  const scene::CameraDesc cam = topView();
  SplatRenderer r(96, 96);
  const scene::CameraFrame cf = cameraFrame(cam, 1.0f);
  const frame::Lighting light;
  const frame::RenderImage ref =
      raymarchReference(f, surfaceThresholdAuto(f) * f.meanDensity(), cam, 96, 96, light);
  SplatParams newton;
  newton.projection = SplatParams::Projection::Newton;
  const SplatFrame points = buildSplats(f, SplatParams{}, SplatKind::Point, cf.projView, cf.eye);
  const SplatFrame quads = buildSplats(f, newton, SplatKind::Quad, cf.projView, cf.eye);
  const frame::ImageError ep = frame::compareImages(
      r.render(points, SplatKind::Point, cam, light, frame::ImageContents::ColourAndNormals), ref);
  const frame::ImageError eq = frame::compareImages(
      r.render(quads, SplatKind::Quad, cam, light, frame::ImageContents::ColourAndNormals), ref);
  std::printf(
      "block from above: point PSNR %.2f holes %.4f normal %.2f deg; quad PSNR %.2f holes %.4f "
      "normal %.2f deg\n",
      ep.psnr, ep.holeFraction, ep.normalErrorDegrees, eq.psnr, eq.holeFraction,
      eq.normalErrorDegrees);
  // Thresholds: the measured figures (llvmpipe, 2026-11-22) with a margin for other drivers'
  // rasterisation rules. The splats cover what the reference covers, and the pyramids' vertex
  // normals follow the surface better than the points' one normal.
  EXPECT_LT(ep.holeFraction, 0.05);
  EXPECT_LT(eq.holeFraction, 0.05);
  EXPECT_LT(eq.normalErrorDegrees, ep.normalErrorDegrees);
  EXPECT_GT(eq.psnr, ep.psnr);
}

// A jet two particles wide above a pool: its D stays below SD, so the SD reference has no jet.
// The particles' balls show it, and the quad splats draw it at about its width: a splat whose
// SD surface is out of reach stays flat where it is instead of collapsing onto the jet's axis.
TEST_F(SplatGl, AJetBelowTheSurfaceDensityIsDrawnAtItsWidth) {
  const float dx = 0.01f;
  Block b(12, 4, 12, dx);
  for (int j = 0; j < 16; ++j)  // a vertical jet from 1.5 spacings above the pool
    for (int i = 0; i < 4; ++i)
      b.x.push_back(0.06f + (i % 2) * dx), b.y.push_back(0.055f + j * dx),
          b.z.push_back(0.06f + (i / 2) * dx);
  const DensityField f = b.field(dx);
  scene::CameraDesc side;
  side.position = Vec3(0.065f, 0.12f, 0.75f), side.target = Vec3(0.065f, 0.12f, 0.0f);
  side.fovYDegrees = 25;
  const int size = 128;
  SplatRenderer r(size, size);
  const frame::Lighting light;
  const float SD = surfaceThresholdAuto(f) * f.meanDensity();
  const frame::RenderImage ref = raymarchReference(f, SD, side, size, size, light);
  const float radius = std::cbrt(3.0f / (4.0f * static_cast<float>(solver::kPi))) * dx;
  const frame::RenderImage balls = raytraceParticleBalls(f, radius, side, size, size, light);
  SplatParams newton;
  newton.projection = SplatParams::Projection::Newton;
  const scene::CameraFrame cf = cameraFrame(side, 1.0f);
  const frame::RenderImage quads =
      r.render(buildSplats(f, newton, SplatKind::Quad, cf.projView, cf.eye), SplatKind::Quad, side,
               light, frame::ImageContents::ColourAndNormals);
  const frame::ThinCoverage jet = frame::thinCoverage(quads, ref, balls);
  std::printf("jet: %zu pixels of balls beyond SD, quads cover %.1f%%\n", jet.pixels,
              100 * jet.fraction);
  // A pixel column through the jet, well above the pool: balls and quads, no SD surface.
  const std::size_t above = (size / 2 - 30) * size + size / 2;
  EXPECT_FALSE(ref.covered[above]);
  EXPECT_TRUE(balls.covered[above]);
  EXPECT_TRUE(quads.covered[above]);
  EXPECT_GT(jet.pixels, 200u);
  // Measured 2026-11-25 on llvmpipe: 51% (the splats facing away are culled); with every vertex
  // moved towards the SD surface, as before, 15%.
  EXPECT_GT(jet.fraction, 0.4);
}

// A frame without particles (a pour before its first layer): neither reference has anything to
// hit. The SD reference used to march an unbounded box against a NaN SD and covered every pixel.
TEST_F(SplatGl, ReferencesOfAnEmptyFrameCoverNothing) {
  const DensityField f(nullptr, nullptr, nullptr, 0, 0.01f, 2.5f);
  const frame::Lighting light;
  const scene::CameraDesc cam = topView();
  const float SD = surfaceThresholdAuto(f) * f.meanDensity();
  for (const frame::RenderImage& image : {raymarchReference(f, SD, cam, 32, 32, light),
                                          raytraceParticleBalls(f, 0.006f, cam, 32, 32, light)}) {
    std::size_t covered = 0;
    for (std::uint8_t c : image.covered) covered += c;
    EXPECT_EQ(covered, 0u);
    EXPECT_EQ(image.rgb[0], frame::toSrgb8(light.background[0]));
  }
}

TEST_F(SplatGl, PicturesSkipTheNormalTargetAndKeepTheSameColours) {
  const float dx = 0.01f;
  const Block b(8, 8, 8, dx);
  const DensityField f(b.x.data(), b.y.data(), b.z.data(), b.x.size(), dx, 2.5f);
  const scene::CameraDesc cam = topView();
  const scene::CameraFrame cf = cameraFrame(cam, 1.0f);
  const SplatFrame quads = buildSplats(f, SplatParams{}, SplatKind::Quad, cf.projView, cf.eye);
  ASSERT_GT(quads.splats(), 0u);
  SplatRenderer r(64, 64);
  const frame::RenderImage scored = r.render(quads, SplatKind::Quad, cam, frame::Lighting{},
                                             frame::ImageContents::ColourAndNormals);
  const frame::RenderImage picture = r.render(quads, SplatKind::Quad, cam, frame::Lighting{});
  EXPECT_TRUE(scored.hasNormals());
  EXPECT_FALSE(picture.hasNormals());
  EXPECT_EQ(picture.rgb, scored.rgb);
  EXPECT_GT(std::count(scored.covered.begin(), scored.covered.end(), 1), 100);
  EXPECT_THROW(frame::compareImages(picture, scored), std::invalid_argument);
}

TEST_F(SplatGl, EmptyFrameDrawsOnlyBackground) {
  SplatRenderer r(16, 16);
  const frame::RenderImage img =
      r.render(SplatFrame{}, SplatKind::Quad, topView(), frame::Lighting{},
               frame::ImageContents::ColourAndNormals);
  for (std::uint8_t c : img.covered) EXPECT_EQ(c, 0);
  EXPECT_EQ(img.rgb[0], frame::toSrgb8(frame::Lighting{}.background.x()));
}

}  // namespace
}  // namespace sph::render::splat
