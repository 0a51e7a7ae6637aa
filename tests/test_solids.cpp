// render/solids: the scene's solids as triangle meshes (CPU) and drawn lit and opaque in the
// splat frame (GL on llvmpipe): every triangle lies on the solid's surface with its winding and
// normals pointing out of it, closed solids are closed, the picture shows a solid in front of
// the water and not behind it, and the error figures' frame never sees a solid. Drawn nearest
// shape first: the order is the distance's, and the picture the same as in the order given.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

#include "render/frame/ExtraLights.h"
#include "render/gl/GlContext.h"
#include "render/solids/DrawOrder.h"
#include "render/solids/SolidMesh.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/ReferenceRaymarcher.h"
#include "render/splat/SplatBuilder.h"
#include "render/splat/SplatRenderer.h"
#include "sim/scene/Solid.h"

namespace sph::render::solids {
namespace {

const Aabb kDomain{Vec3(-1, -1, -1), Vec3(1, 1, 1)};

std::vector<scene::BoundaryShape> everyShape() {
  std::vector<scene::BoundaryShape> shapes(6);
  shapes[0].kind = scene::BoundaryShape::Kind::Tank;  // open top
  shapes[0].lo = Vec3(0, 0, 0), shapes[0].hi = Vec3(0.4f, 0.3f, 0.2f);
  shapes[1] = shapes[0], shapes[1].openTop = false;
  shapes[2].kind = scene::BoundaryShape::Kind::Block;
  shapes[2].lo = Vec3(0.1f, 0, 0.1f), shapes[2].hi = Vec3(0.2f, 0.05f, 0.15f);
  shapes[3].kind = scene::BoundaryShape::Kind::Cup;
  shapes[3].centre = Vec3(0.2f, 0.01f, 0.1f), shapes[3].radius = 0.05f, shapes[3].height = 0.08f;
  shapes[4].kind = scene::BoundaryShape::Kind::Sphere;
  shapes[4].centre = Vec3(0.1f, 0.2f, 0.1f), shapes[4].radius = 0.04f;
  shapes[5].kind = scene::BoundaryShape::Kind::Plane;
  shapes[5].point = Vec3(0, -0.1f, 0), shapes[5].normal = Vec3(0.1f, 1, 0).normalized();
  return shapes;
}

Vec3 at(const SolidVertex& v) {
  return Vec3(v.position[0], v.position[1], v.position[2]);
}
Vec3 normalOf(const SolidVertex& v) {
  return Vec3(v.normal[0], v.normal[1], v.normal[2]);
}

TEST(SolidMesh, EveryTriangleLiesOnTheSurfaceFacingOutOfTheSolid) {
  const float thickness = 0.02f;
  for (const scene::BoundaryShape& shape : everyShape()) {
    const SolidMesh m = tessellate(shape, kDomain, thickness, 48);
    const scene::Solid solid(shape, thickness);
    ASSERT_FALSE(m.indices.empty());
    ASSERT_EQ(m.indices.size() % 3, 0u);
    std::size_t degenerate = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const SolidVertex &a = m.vertices[m.indices[t]], &b = m.vertices[m.indices[t + 1]],
                        &c = m.vertices[m.indices[t + 2]];
      const Vec3 face = (at(b) - at(a)).cross(at(c) - at(a));
      if (face.norm() < 1e-12f) {
        ++degenerate;  // a fan's centre (the cup's floor)
        continue;
      }
      // Counter-clockwise seen from where the normals point.
      EXPECT_GT(face.normalized().dot(normalOf(a)), 0.5f) << static_cast<int>(shape.kind);
      // On the surface, with the normal pointing out of the solid: a little way along it is
      // outside, a little way against it inside (the sphere's facets sit inside the sphere).
      const Vec3 centre = (at(a) + at(b) + at(c)) / 3;
      const Vec3 n = normalOf(a);
      EXPECT_NEAR(solid.distance(centre), 0.0f, 2e-3f) << static_cast<int>(shape.kind);
      EXPECT_GT(solid.distance(centre + 4e-3f * n), 0.0f) << static_cast<int>(shape.kind);
      if (shape.kind != scene::BoundaryShape::Kind::Plane) {
        EXPECT_LT(solid.distance(centre - 4e-3f * n), 0.0f) << static_cast<int>(shape.kind);
      }
    }
    EXPECT_LE(degenerate, 96u);
  }
}

// Closed solids: every edge (by position) is shared by exactly two triangles, once each way.
// (A tank is a cut-away, a plane a quad.)
TEST(SolidMesh, ClosedSolidsHaveNoOpenEdge) {
  for (const scene::BoundaryShape& shape : everyShape()) {
    if (shape.kind == scene::BoundaryShape::Kind::Plane ||
        shape.kind == scene::BoundaryShape::Kind::Tank)
      continue;
    const SolidMesh m = tessellate(shape, kDomain, 0.02f, 32);
    using Key = std::tuple<long, long, long>;
    auto key = [](const SolidVertex& v) {
      return Key(std::lround(v.position[0] * 1e5), std::lround(v.position[1] * 1e5),
                 std::lround(v.position[2] * 1e5));
    };
    std::map<std::pair<Key, Key>, int> directed;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      for (int e = 0; e < 3; ++e) {
        const Key p = key(m.vertices[m.indices[t + e]]),
                  q = key(m.vertices[m.indices[t + (e + 1) % 3]]);
        if (p != q) directed[{p, q}] += 1;
      }
    }
    std::size_t open = 0;
    for (const auto& [edge, count] : directed) {
      if (count != 1 || directed.count({edge.second, edge.first}) == 0) ++open;
    }
    EXPECT_EQ(open, 0u) << "shape " << static_cast<int>(shape.kind);
  }
}

TEST(SolidMesh, AreasMatchTheShapes) {
  auto area = [](const SolidMesh& m) {
    double a = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
      a += 0.5 * (at(m.vertices[m.indices[t + 1]]) - at(m.vertices[m.indices[t]]))
                     .cross(at(m.vertices[m.indices[t + 2]]) - at(m.vertices[m.indices[t]]))
                     .norm();
    return a;
  };
  const auto shapes = everyShape();
  EXPECT_NEAR(area(tessellate(shapes[2], kDomain, 0.02f)),
              2 * (0.1 * 0.05 + 0.1 * 0.05 + 0.05 * 0.05), 1e-6);
  EXPECT_NEAR(area(tessellate(shapes[4], kDomain, 0.02f, 96)), 4 * M_PI * 0.04 * 0.04,
              0.01 * 4 * M_PI * 0.04 * 0.04);
}

// Distances by hand: a sphere's is to its surface, a block's and a cup's to their boxes (0 from
// inside), a plane and a tank go last; ties keep their given order.
TEST(DrawOrder, NearestFirstPlanesAndTanksLast) {
  const std::vector<scene::BoundaryShape> shapes = everyShape();
  // tank, closed tank, block [0.1, 0.2] x [0, 0.05] x [0.1, 0.15], cup at (0.2, 0.01, 0.1)
  // r 0.05 h 0.08, sphere at (0.1, 0.2, 0.1) r 0.04, plane.
  const Vec3 eye(0.15f, 1.0f, 0.1f);
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(nearestDistance(shapes[0], 0.01f, eye), inf);
  EXPECT_EQ(nearestDistance(shapes[1], 0.01f, eye), inf);
  EXPECT_NEAR(nearestDistance(shapes[2], 0.01f, eye), 1.0f - 0.05f, 1e-6f);
  EXPECT_NEAR(nearestDistance(shapes[3], 0.01f, eye), 1.0f - 0.09f, 1e-6f);  // the rim
  EXPECT_NEAR(nearestDistance(shapes[4], 0.01f, eye), std::hypot(0.05f, 0.8f) - 0.04f, 1e-6f);
  EXPECT_EQ(nearestDistance(shapes[5], 0.01f, eye), inf);
  EXPECT_EQ(nearestDistance(shapes[2], 0.01f, Vec3(0.15f, 0.01f, 0.12f)), 0.0f) << "inside";
  EXPECT_EQ(frontToBack(shapes, 0.01f, eye), (std::vector<std::size_t>{4, 3, 2, 0, 1, 5}));
  // Below the cup's underside (at y = 0): the cup 0.05 m away, the block's corner 0.07 m.
  EXPECT_EQ(frontToBack(shapes, 0.01f, Vec3(0.2f, -0.05f, 0.05f))[0], 3u);
}

class SolidsGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

// A block between the camera and a splat hides it in the picture and in the scored frame (the
// error figures' reference has the same solids: `compare` draws them in every panel); the normal
// target stays the water's.
TEST_F(SolidsGl, AnOpaqueSolidHidesTheWaterBehindIt) {
  splat::SplatRenderer r(32, 32);
  scene::CameraDesc top;
  top.position = Vec3(0, 1, 0), top.target = Vec3::Zero(), top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 30;
  splat::SplatFrame water;
  water.halfSize = 0.2f;
  water.points.push_back(splat::SplatVertex{{0, 0, 0}, {0, 1, 0}});
  scene::BoundaryShape block;
  block.kind = scene::BoundaryShape::Kind::Block;
  block.lo = Vec3(-0.05f, 0.2f, -0.05f), block.hi = Vec3(0.05f, 0.3f, 0.05f);
  SolidRenderer solids({block}, kDomain, 0.01f);
  solids.material.colour = Vec3(0.9f, 0.1f, 0.1f);
  r.setLayers({&solids});
  frame::Lighting light;
  const frame::RenderImage picture = r.render(water, splat::SplatKind::Point, top, light);
  const std::size_t centre = 16 * 32 + 16, edge = 16 * 32 + 24;
  EXPECT_GT(picture.rgb[3 * centre], picture.rgb[3 * centre + 2] + 60) << "the red block in front";
  EXPECT_GT(picture.rgb[3 * edge + 2], picture.rgb[3 * edge]) << "blue water around it";
  const frame::RenderImage scored =
      r.render(water, splat::SplatKind::Point, top, light, frame::ImageContents::ColourAndNormals);
  EXPECT_FALSE(scored.covered[centre]) << "the block hides the water";
  EXPECT_EQ(scored.rgb[3 * centre], picture.rgb[3 * centre]) << "the block, as in the picture";
}

// The reference ray-marcher ends its rays on the solids GL drew (the backdrop): where the block
// hides the water the reference shows the block's pixels, uncovered, as the splats' frame does,
// and the splats still score as they do on water alone.
TEST_F(SolidsGl, TheReferenceEndsItsRaysOnTheSolids) {
  const int size = 64;
  splat::SplatRenderer r(size, size);
  scene::CameraDesc top;
  top.position = Vec3(0.05f, 0.6f, 0.05f), top.target = Vec3(0.05f, 0, 0.05f);
  top.up = Vec3(0, 0, -1), top.fovYDegrees = 20;
  // A pool of 10 x 4 x 10 particles, 1 cm apart, from the origin; a red block above its middle.
  std::vector<float> x, y, z;
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 10; ++i)
        x.push_back(0.01f * (i + 0.5f)), y.push_back(0.01f * (j + 0.5f)),
            z.push_back(0.01f * (k + 0.5f));
  const splat::DensityField field(x.data(), y.data(), z.data(), x.size(), 0.01f, 2.5f);
  scene::BoundaryShape block;
  block.kind = scene::BoundaryShape::Kind::Block;
  block.lo = Vec3(0.04f, 0.1f, 0.04f), block.hi = Vec3(0.06f, 0.12f, 0.06f);
  SolidRenderer solids({block}, kDomain, 0.01f);
  solids.material.colour = Vec3(0.9f, 0.1f, 0.1f);
  r.setLayers({&solids});
  const frame::Lighting light;
  const float SD = splat::surfaceThresholdAuto(field) * field.meanDensity();
  const splat::Backdrop backdrop = r.drawBackdrop(top, light);
  const frame::RenderImage ref =
      splat::raymarchReference(field, SD, top, size, size, light, &backdrop);
  const scene::CameraFrame cf = cameraFrame(top, 1.0f);
  splat::SplatParams newton;
  newton.projection = splat::SplatParams::Projection::Newton;
  const splat::SplatFrame quads =
      splat::buildSplats(field, newton, splat::SplatKind::Quad, cf.projView, cf.eye);
  const frame::RenderImage scored =
      r.render(quads, splat::SplatKind::Quad, top, light, frame::ImageContents::ColourAndNormals);
  const std::size_t centre = (size / 2) * size + size / 2, pool = (size / 2) * size + 20;
  EXPECT_TRUE(std::isfinite(backdrop.viewDepth[centre]));
  EXPECT_NEAR(backdrop.viewDepth[centre], 0.6f - 0.12f, 1e-3f) << "the block's top, 0.48 m away";
  EXPECT_FALSE(std::isfinite(backdrop.viewDepth[0])) << "nothing in the corner";
  EXPECT_FALSE(ref.covered[centre]);
  EXPECT_FALSE(scored.covered[centre]);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(ref.rgb[3 * centre + k], backdrop.rgb[3 * centre + k]);
  EXPECT_GT(ref.rgb[3 * centre], ref.rgb[3 * centre + 2] + 60) << "red block";
  EXPECT_TRUE(ref.covered[pool]);
  EXPECT_TRUE(scored.covered[pool]);
  const frame::ImageError e = frame::compareImages(scored, ref);
  EXPECT_LT(e.holeFraction, 0.05);
  EXPECT_GT(e.psnr, 25.0);
}

// A deferred pipeline with no lights of its own: the frame goes through the G-buffer and the
// lighting pass, which add nothing (the hook's switches off).
class DeferredWithoutLights : public frame::ExtraLights {
 public:
  void apply(GLuint program) const override { frame::applyExtraLights(program, frame::Lighting{}); }
  bool deferred() const override { return true; }
};

// Fig. 11's kind of frame in small: a floor drawn first in the order given, spheres and blocks
// over it and over each other. Nearest first, the picture is the same to the bit (the depth test
// keeps the nearest surface either way), forward and into the deferred G-buffer.
TEST_F(SolidsGl, DrawnNearestFirstThePictureIsTheSame) {
  std::vector<scene::BoundaryShape> shapes;
  scene::BoundaryShape floor;
  floor.kind = scene::BoundaryShape::Kind::Plane, floor.point = Vec3(0, -0.5f, 0);
  shapes.push_back(floor);
  for (int i = 0; i < 4; ++i) {
    scene::BoundaryShape s;
    s.kind = scene::BoundaryShape::Kind::Sphere;
    s.centre = Vec3(-0.45f + 0.3f * i, -0.3f, -0.5f + 0.35f * i), s.radius = 0.2f;
    shapes.push_back(s);
    scene::BoundaryShape b;
    b.kind = scene::BoundaryShape::Kind::Block;
    b.lo = Vec3(-0.5f + 0.3f * i, -0.5f, -0.3f + 0.35f * i), b.hi = b.lo + Vec3(0.15f, 0.4f, 0.1f);
    shapes.push_back(b);
  }
  scene::CameraDesc camera;
  camera.position = Vec3(0.1f, 0.6f, 1.6f), camera.target = Vec3(0, -0.4f, 0);
  camera.fovYDegrees = 50;
  const std::vector<std::size_t> order = frontToBack(shapes, 0.01f, camera.position);
  ASSERT_EQ(order.back(), 0u) << "the floor last";
  splat::SplatRenderer r(160, 120);
  SolidRenderer solids(shapes, kDomain, 0.01f);
  r.setLayers({&solids});
  const DeferredWithoutLights deferredPipeline;
  for (bool deferred : {false, true}) {
    SCOPED_TRACE(deferred ? "deferred" : "forward");
    frame::Lighting lighting;
    if (deferred) lighting.extra = &deferredPipeline;
    solids.frontToBack = true;
    const frame::RenderImage a =
        r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
    EXPECT_EQ(r.lastPasses().gbuffer > 0, deferred) << "the G-buffer pass ran";
    solids.frontToBack = false;
    const frame::RenderImage b =
        r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
    std::size_t spheres = 0;
    for (std::size_t i = 0; i < a.rgb.size(); i += 3) spheres += a.rgb[i] != a.rgb[0];
    EXPECT_GT(spheres, a.rgb.size() / 3 / 4) << "something drawn";
    EXPECT_EQ(a.rgb, b.rgb);
  }
}

// A tank seen from outside: its near wall is culled, so the water inside shows.
TEST_F(SolidsGl, ATankIsACutAwayFromOutside) {
  splat::SplatRenderer r(32, 32);
  scene::CameraDesc side;
  side.position = Vec3(0.2f, 0.1f, 1.5f), side.target = Vec3(0.2f, 0.1f, 0.1f);
  side.fovYDegrees = 20;
  splat::SplatFrame water;
  water.halfSize = 0.08f;
  water.points.push_back(splat::SplatVertex{{0.2f, 0.1f, 0.1f}, {0, 0, 1}});
  scene::BoundaryShape tank;
  tank.kind = scene::BoundaryShape::Kind::Tank;
  tank.lo = Vec3(0, 0, 0), tank.hi = Vec3(0.4f, 0.3f, 0.2f);
  SolidRenderer solids({tank}, kDomain, 0.02f);
  r.setLayers({&solids});
  const frame::RenderImage picture =
      r.render(water, splat::SplatKind::Point, side, frame::Lighting{});
  const std::size_t centre = 16 * 32 + 16;
  EXPECT_GT(picture.rgb[3 * centre + 2], picture.rgb[3 * centre] + 40) << "blue water shows";
}

}  // namespace
}  // namespace sph::render::solids
