// render/solids/ScreenTessellation: the spheres and cups tessellated for their size on screen.
// The rule meets its bound with the fewest segments (a multiple of 4), the radius on screen is
// the projection's, the count falls with distance and rises as a sphere fills the frame, the mesh
// is rebuilt only when a count changes, and the picture is the fixed 64-segment one's within a
// stated bound.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/gl/GlContext.h"
#include "render/solids/ScreenTessellation.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"

namespace sph::render::solids {
namespace {

const Aabb kDomain{Vec3(-10, -1, -10), Vec3(10, 10, 10)};

TEST(ScreenTessellation, TheFewestSegmentsThatMeetTheBound) {
  const TessellationBound b;  // 0.5 px, 8 to 128
  for (float r = 1.0f; r < 2000.0f; r *= 1.17f) {
    const int n = segmentsFor(r, b);
    ASSERT_EQ(n % 4, 0) << r;
    ASSERT_GE(n, b.floor) << r;
    ASSERT_LE(n, b.cap) << r;
    const double error = r * std::pow(std::sin(M_PI / n), 2);
    if (n < b.cap) {
      EXPECT_LE(error, b.pixels * (1 + 1e-6)) << r << " px, " << n << " segments";
    }
    if (n > b.floor) {
      EXPECT_GT(r * std::pow(std::sin(M_PI / (n - 4)), 2), b.pixels) << "4 fewer would do";
    }
  }
  // Hand-computed: r = 50 px needs pi / n <= asin(0.1) = 0.10017, n >= 31.36: 32.
  EXPECT_EQ(segmentsFor(50.0f, b), 32);
  EXPECT_EQ(segmentsFor(0.0f, b), 8) << "outside the view: the floor";
  EXPECT_EQ(segmentsFor(std::numeric_limits<float>::infinity(), b), 128) << "at the eye: the cap";
  EXPECT_EQ(segmentsFor(1e5f, b), 128);
  TessellationBound fixed;
  fixed.floor = fixed.cap = 64;
  EXPECT_EQ(segmentsFor(3.0f, fixed), 64);
  EXPECT_EQ(segmentsFor(3000.0f, fixed), 64);
}

TEST(ScreenTessellation, TheRadiusOnScreenIsTheProjections) {
  scene::CameraDesc c;
  c.position = Vec3(0, 0, 10), c.target = Vec3::Zero(), c.fovYDegrees = 60;
  c.near = 0.1f, c.far = 100;
  const int w = 800, h = 600;
  const scene::CameraFrame f = cameraFrame(c, static_cast<float>(w) / h);
  const float focal = 0.5f * h / std::tan(static_cast<float>(M_PI) / 6);  // px per m at depth 1
  // On the axis: the radius at the depth of the nearest point, 10 - 1 m.
  EXPECT_NEAR(radiusOnScreen(f.projView, w, h, Vec3::Zero(), 1.0f, 1.0f), focal / 9, 1e-3f * focal);
  // Off the axis at the same depth: wider by 1 / cos of the angle (3 m across at 10 m).
  const float off = radiusOnScreen(f.projView, w, h, Vec3(3, 0, 0), 1.0f, 1.0f);
  EXPECT_NEAR(off, focal / 9 * std::sqrt(1.0f + 0.09f), 1e-3f * focal);
  EXPECT_EQ(radiusOnScreen(f.projView, w, h, Vec3(0, 0, 20), 1.0f, 1.0f), 0.0f) << "behind";
  EXPECT_EQ(radiusOnScreen(f.projView, w, h, Vec3(30, 0, 0), 1.0f, 1.0f), 0.0f) << "aside";
  EXPECT_TRUE(std::isinf(radiusOnScreen(f.projView, w, h, Vec3(0, 0, 9.5f), 1.0f, 1.0f)))
      << "the eye inside the sphere";
}

class TessellationGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

scene::BoundaryShape sphereAt(const Vec3& centre, float radius) {
  scene::BoundaryShape s;
  s.kind = scene::BoundaryShape::Kind::Sphere, s.centre = centre, s.radius = radius;
  return s;
}

scene::CameraDesc lookingAt(const Vec3& eye, const Vec3& target) {
  scene::CameraDesc c;
  c.position = eye, c.target = target, c.fovYDegrees = 50, c.near = 0.05f, c.far = 100;
  return c;
}

frame::RenderImage picture(splat::SplatRenderer& r, const scene::CameraDesc& camera) {
  return r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, frame::Lighting{});
}

// One sphere of 1 m seen from 40, 10 and 1.3 m: fewer segments far, more than the fixed 64
// where it fills the frame, and the mesh rebuilt only when the count changes.
TEST_F(TessellationGl, TheCountFollowsTheSizeOnScreen) {
  splat::SplatRenderer r(320, 240);
  SolidRenderer solids({sphereAt(Vec3::Zero(), 1.0f)}, kDomain, 0.01f);
  r.setLayers({&solids});
  EXPECT_EQ(solids.meshBuilds(), 0u) << "nothing before the first draw";
  int previous = 0;
  for (float d : {40.0f, 10.0f, 1.3f}) {
    picture(r, lookingAt(Vec3(0, 0, d), Vec3::Zero()));
    const int n = solids.segments()[0];
    // r (n / 2 rings): 2 n (n / 2 - 1) triangles, fans at the poles.
    EXPECT_EQ(solids.triangles(), static_cast<std::size_t>(n * (n - 2))) << d;
    if (d == 40.0f) {
      EXPECT_LE(n, 16) << "~7 px across";
    }
    if (d == 1.3f) {
      EXPECT_GT(n, 64) << "filling the frame";
    }
    EXPECT_GT(n, previous) << "nearer, more segments";
    previous = n;
  }
  EXPECT_EQ(solids.meshBuilds(), 3u);
  const scene::CameraDesc still = lookingAt(Vec3(0, 0, 10), Vec3::Zero());
  picture(r, still);
  const std::size_t builds = solids.meshBuilds();
  picture(r, still);
  picture(r, lookingAt(Vec3(0.001f, 0, 10), Vec3::Zero()));
  EXPECT_EQ(solids.meshBuilds(), builds) << "a still (or barely moving) camera rebuilds nothing";
  picture(r, lookingAt(Vec3(0, 0, 10), Vec3(30, 0, 0)));
  EXPECT_EQ(solids.segments()[0], 8) << "out of view: the floor";
}

// The cup's walls and rims follow its size too.
TEST_F(TessellationGl, ACupFollowsItsSizeOnScreen) {
  splat::SplatRenderer r(320, 240);
  scene::BoundaryShape cup;
  cup.kind = scene::BoundaryShape::Kind::Cup;
  cup.centre = Vec3::Zero(), cup.radius = 0.5f, cup.height = 0.6f;
  SolidRenderer solids({cup}, kDomain, 0.05f);
  r.setLayers({&solids});
  picture(r, lookingAt(Vec3(0, 2, 20), Vec3(0, 0.3f, 0)));
  const int far = solids.segments()[0];
  picture(r, lookingAt(Vec3(0, 1, 2), Vec3(0, 0.3f, 0)));
  const int near = solids.segments()[0];
  EXPECT_LT(far, near);
  EXPECT_LE(far, 16) << "~30 px across";
  EXPECT_GE(near, 40) << "filling a third of the frame";
}

// Spheres from 6 to 150 px across, a cup and a floor, against the same frame with every round
// shape at the fixed 64 segments of before. The bound: a silhouette within 0.5 px moves the
// coverage of the pixels it crosses, so those may differ in full; elsewhere the faces are flatter
// by at most 0.5 px of depth and the interpolated normal is the true one of a point that near, so
// the shading differs by a few steps at most.
TEST_F(TessellationGl, ThePictureIsTheFixedTessellationsWithinTheBound) {
  const int w = 320, h = 240;
  std::vector<scene::BoundaryShape> shapes;
  scene::BoundaryShape floor;
  floor.kind = scene::BoundaryShape::Kind::Plane, floor.point = Vec3::Zero(),
  floor.normal = Vec3::UnitY();
  shapes.push_back(floor);
  for (int i = 0; i < 5; ++i)
    shapes.push_back(sphereAt(Vec3(-4.0f + 2.0f * i, 0.6f, -3.0f * i), 0.6f));
  shapes.push_back(sphereAt(Vec3(0.4f, 0.8f, 3.2f), 0.8f));
  scene::BoundaryShape cup;
  cup.kind = scene::BoundaryShape::Kind::Cup;
  cup.centre = Vec3(-1.5f, 0.05f, 2.5f), cup.radius = 0.4f, cup.height = 0.5f;
  shapes.push_back(cup);
  const scene::CameraDesc camera = lookingAt(Vec3(0, 2.5f, 7), Vec3(0, 0.5f, 0));
  splat::SplatRenderer r(w, h);
  SolidRenderer adaptive(shapes, kDomain, 0.05f);
  r.setLayers({&adaptive});
  const frame::RenderImage a = picture(r, camera);
  SolidRenderer fixed(shapes, kDomain, 0.05f);
  fixed.tessellation.floor = fixed.tessellation.cap = 64;
  r.setLayers({&fixed});
  const frame::RenderImage b = picture(r, camera);
  EXPECT_LT(adaptive.triangles(), fixed.triangles() / 2) << "the point of it";
  std::size_t differing = 0, beyondFew = 0;
  int worstInside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      int d = 0;
      for (int k = 0; k < 3; ++k)
        d = std::max(d, std::abs(int(a.rgb[3 * i + k]) - b.rgb[3 * i + k]));
      differing += d > 1;
      if (d <= 4) continue;
      ++beyondFew;
      // More than a few steps only next to a silhouette: a neighbour of the fixed picture
      // differs from this pixel by as much (a pixel the outline crosses).
      int edge = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
          const std::size_t j = static_cast<std::size_t>(yy) * w + xx;
          for (int k = 0; k < 3; ++k)
            edge = std::max(edge, std::abs(int(b.rgb[3 * i + k]) - b.rgb[3 * j + k]));
        }
      if (edge < d / 2) worstInside = std::max(worstInside, d);
    }
  const std::size_t n = static_cast<std::size_t>(w) * h;
  EXPECT_LT(differing, n / 100) << "pixels more than one step apart";
  EXPECT_LT(beyondFew, n / 400) << "pixels more than 4 steps apart";
  EXPECT_EQ(worstInside, 0) << "more than 4 steps away from any outline";
}

}  // namespace
}  // namespace sph::render::solids
