// The CPU half of the splat renderer (seed 003): the density field, surface detection, normals,
// eq. (6) and the reference ray-marcher with its error figures. No GL needed.
#include <gtest/gtest.h>

#include <cmath>

#include "render/splat/DensityField.h"
#include "render/splat/ReferenceRaymarcher.h"
#include "render/splat/SplatBuilder.h"
#include "render/splat/SplatRenderer.h"
#include "tests/LatticeBlock.h"

namespace sph::render::splat {
namespace {

using test::Block;

scene::CameraDesc lookingDownAt(const Vec3& target, float distance) {
  scene::CameraDesc c;
  c.position = target + Vec3(0.3f, 1.0f, 0.4f).normalized() * distance;
  c.target = target;
  return c;
}

TEST(DensityField, ReadsRestDensityInsideAndPointsInwardAtTheSurface) {
  const float dx = 0.01f;
  const Block b(12, 12, 12, dx);
  const DensityField f = b.field(dx);
  const Vec3 centre(0.06f, 0.06f, 0.06f);
  EXPECT_NEAR(f.density(centre + Vec3(0.005f, 0.005f, 0.005f)), 1000.0f, 0.5f);  // a lattice site
  // Above the top face the density falls, and its gradient (eq. (4)) points down, into the fluid.
  const Vec3 above(0.06f, 0.12f + 0.3f * dx, 0.06f);
  EXPECT_LT(f.density(above), 500.0f);
  const Vec3 g = f.gradient(above).normalized();
  EXPECT_LT(g.y(), -0.99f);
  EXPECT_GT(f.flatSurfaceFraction(), 0.5f);
  EXPECT_LT(f.flatSurfaceFraction(), 0.95f);
}

TEST(SplatBuilder, SurfaceIsTheOuterLayerAndInteriorParticlesMakeNothing) {
  const float dx = 0.01f;
  const Block b(10, 10, 10, dx);  // a small block: its mean density ID is well below the bulk
  const DensityField f = b.field(dx);
  const scene::CameraDesc cam = lookingDownAt(Vec3(0.05f, 0.05f, 0.05f), 0.5f);
  const scene::CameraFrame cf = cameraFrame(cam, 4.0f / 3.0f);
  const SplatFrame quads = buildSplats(f, SplatParams{}, SplatKind::Quad, cf.projView, cf.eye);
  // Every particle of the outer shell, and none deeper than the second layer.
  EXPECT_GE(quads.surface, 10u * 10u * 10u - 8u * 8u * 8u);
  EXPECT_LE(quads.surface, 10u * 10u * 10u - 6u * 6u * 6u);
  EXPECT_EQ(quads.quads.size(), 5 * quads.splats());
  EXPECT_EQ(quads.indices.size(), 12 * quads.splats());
  const SplatFrame points = buildSplats(f, SplatParams{}, SplatKind::Point, cf.projView, cf.eye);
  EXPECT_EQ(points.points.size(), quads.splats());
  EXPECT_NEAR(quads.SD / quads.ID, surfaceThresholdAuto(f), 1e-6f);
  EXPECT_NEAR(quads.SD, 0.5f * (1 + f.flatSurfaceFraction()) * 1000.0f, 0.01f);
}

TEST(SplatBuilder, EquationSixMovesVerticesTowardsTheIsoSurface) {
  const float dx = 0.01f;
  const Block b(16, 16, 16, dx);
  const DensityField f = b.field(dx);
  const scene::CameraDesc cam = lookingDownAt(Vec3(0.08f, 0.08f, 0.08f), 0.6f);
  const scene::CameraFrame cf = cameraFrame(cam, 1.0f);
  SplatParams flatParams;
  flatParams.pyramid = false;
  const SplatFrame flat = buildSplats(f, flatParams, SplatKind::Quad, cf.projView, cf.eye);
  // Summed |D - SD| at the vertices on the faces (vertex normals along an axis).
  auto gap = [&](const SplatFrame& frame) {
    double sum = 0;
    for (std::size_t v = 0; v < frame.quads.size(); ++v) {
      const SplatVertex& a = flat.quads[v];  // the same vertices, before eq. (6)
      const SplatVertex& c = frame.quads[v];
      if (std::max({std::abs(a.normal[0]), std::abs(a.normal[1]), std::abs(a.normal[2])}) < 0.99f)
        continue;
      sum += std::abs(f.density(Vec3(c.position[0], c.position[1], c.position[2])) - frame.SD);
    }
    return sum;
  };
  const double before = gap(flat);
  ASSERT_GT(before, 0.0);
  // The paper's eq. (6) moves them towards the surface (it overshoots: it assumes the density
  // rises over a whole kernel radius, the field does so over about one spacing)...
  SplatParams eq6Params;
  eq6Params.projection = SplatParams::Projection::Equation6;
  const SplatFrame eq6 = buildSplats(f, eq6Params, SplatKind::Quad, cf.projView, cf.eye);
  ASSERT_EQ(eq6.quads.size(), flat.quads.size());
  EXPECT_LT(gap(eq6), 0.9 * before);
  // ...and the Newton step puts them on it.
  SplatParams newtonParams;
  newtonParams.projection = SplatParams::Projection::Newton;
  const SplatFrame newton = buildSplats(f, newtonParams, SplatKind::Quad, cf.projView, cf.eye);
  EXPECT_LT(gap(newton), 0.2 * before) << "flat " << before << ", eq. (6) " << gap(eq6);
}

TEST(SplatBuilder, OpaqueWaterDropsBackFacingSplatsAndDrawsNearToFar) {
  const float dx = 0.01f;
  const Block b(10, 10, 10, dx);
  const DensityField f = b.field(dx);
  const scene::CameraDesc cam = lookingDownAt(Vec3(0.05f, 0.05f, 0.05f), 0.5f);
  const scene::CameraFrame cf = cameraFrame(cam, 4.0f / 3.0f);
  const SplatFrame opaque = buildSplats(f, SplatParams{}, SplatKind::Point, cf.projView, cf.eye);
  SplatParams translucentParams;
  translucentParams.translucent = true;
  const SplatFrame translucent =
      buildSplats(f, translucentParams, SplatKind::Point, cf.projView, cf.eye);
  // The camera sees three faces of the cube from above-front-right: the bottom and the three
  // faces away from it (about half the shell) face away and are dropped; blended, all stay.
  ASSERT_EQ(opaque.surface, translucent.surface);
  EXPECT_EQ(translucent.backFacing, 0u);
  EXPECT_EQ(translucent.points.size(), translucent.surface);
  EXPECT_GT(opaque.backFacing, opaque.surface / 3);
  EXPECT_LT(opaque.backFacing, 2 * opaque.surface / 3);
  EXPECT_EQ(opaque.points.size(), opaque.surface - opaque.backFacing);
  for (const SplatVertex& v : opaque.points) {
    const Vec3 toEye = (cf.eye - Vec3(v.position[0], v.position[1], v.position[2])).normalized();
    EXPECT_GE(Vec3(v.normal[0], v.normal[1], v.normal[2]).dot(toEye), -0.3f);
  }
  // The builder's key is its own float arithmetic (built at -O3, which may fuse multiply-adds),
  // this test's another: near-ties may be ordered either way within a few float steps.
  const float rounding = 2e-6f;  // m, at distances under 1 m
  auto distance = [&](const SplatVertex& v) {
    return (cf.eye - Vec3(v.position[0], v.position[1], v.position[2])).norm();
  };
  for (std::size_t k = 1; k < opaque.points.size(); ++k)
    EXPECT_LE(distance(opaque.points[k - 1]), distance(opaque.points[k]) + rounding);
  for (std::size_t k = 1; k < translucent.points.size(); ++k)
    EXPECT_GE(distance(translucent.points[k - 1]) + rounding, distance(translucent.points[k]));
  // render.cull_back_faces = false: opaque, every splat, still near to far.
  SplatParams keepAll;
  keepAll.cullBackFacing = false;
  const SplatFrame all = buildSplats(f, keepAll, SplatKind::Point, cf.projView, cf.eye);
  EXPECT_EQ(all.backFacing, 0u);
  EXPECT_EQ(all.points.size(), all.surface);
  for (std::size_t k = 1; k < all.points.size(); ++k)
    EXPECT_LE(distance(all.points[k - 1]), distance(all.points[k]) + rounding);
}

TEST(SplatBuilder, SplatsOutsideTheFrustumAreNotBuilt) {
  const float dx = 0.01f;
  const Block b(10, 10, 10, dx);
  const DensityField f = b.field(dx);
  scene::CameraDesc away;
  away.position = Vec3(0.05f, 0.05f, 2.0f);
  away.target = Vec3(0.05f, 0.05f, 3.0f);  // looking away from the block
  const scene::CameraFrame cf = cameraFrame(away, 1.0f);
  const SplatFrame s = buildSplats(f, SplatParams{}, SplatKind::Quad, cf.projView, cf.eye);
  EXPECT_EQ(s.surface, 0u);
  EXPECT_GT(s.culled, 8u * 8u * 6u);  // at least the faces' particles were surface and culled
}

TEST(ReferenceRaymarcher, CoversTheBlockAndShadesTheTopFaceLikeTheLightingModel) {
  const float dx = 0.01f;
  const Block b(10, 10, 10, dx);
  const DensityField f = b.field(dx);
  scene::CameraDesc top;
  top.position = Vec3(0.05f, 0.6f, 0.05f);
  top.target = Vec3(0.05f, 0.0f, 0.05f);
  top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 20;
  const frame::Lighting light;
  const float SD = surfaceThresholdAuto(f) * f.meanDensity();
  const frame::RenderImage img = raymarchReference(f, SD, top, 64, 64, light);
  // The centre pixel sees the top face: normal up, colour = shade(up).
  const std::size_t centre = 32 * 64 + 32;
  ASSERT_TRUE(img.covered[centre]);
  EXPECT_GT(img.normal[3 * centre + 1], 0.98f);
  const Vec3 n(img.normal[3 * centre], img.normal[3 * centre + 1], img.normal[3 * centre + 2]);
  const Vec3 toEye = (top.position - Vec3(0.05f, 0.1f, 0.05f)).normalized();
  const Vec3 expected = frame::shade(light, n, toEye);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(img.rgb[3 * centre + k], frame::toSrgb8(expected[k]), 2);
  // The corners see the background.
  EXPECT_FALSE(img.covered[0]);
  EXPECT_EQ(img.rgb[0], frame::toSrgb8(light.background.x()));
}

TEST(RenderImage, ErrorFiguresOfKnownImages) {
  frame::RenderImage a, b;
  a.resize(4, 1), b.resize(4, 1);
  for (int p = 0; p < 4; ++p) {
    b.covered[p] = 1;
    b.normal[3 * p + 1] = 1;
  }
  a.covered = {1, 1, 0, 0};
  a.normal = {0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0};  // pixel 1 is 90 degrees off
  const frame::ImageError e = frame::compareImages(a, b);
  EXPECT_DOUBLE_EQ(e.holeFraction, 0.5);
  EXPECT_NEAR(e.normalErrorDegrees, 45.0, 1e-9);
  EXPECT_EQ(e.psnr, 99.0);  // identical colours
  a.rgb[0] = 255;           // one channel of one pixel off by 255: MSE = 255^2 / 12
  EXPECT_NEAR(frame::compareImages(a, b).psnr, 10 * std::log10(12.0), 1e-9);
}

}  // namespace
}  // namespace sph::render::splat
