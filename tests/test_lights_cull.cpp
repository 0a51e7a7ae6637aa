// Frustum culling of the particle lights (lights.cull; render/lights/LightCulling.h): every voxel
// a visible point's filter reads lies in the culled box; a light just outside the frustum whose
// range reaches into it is kept, one beyond reach is dropped; the culled picture is the unculled
// one to the bit (forward and deferred, every filter) although most lights and voxels are skipped,
// and the lights just outside the view do light it; a camera that moves leaves no stale voxels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "render/gl/GlContext.h"
#include "render/lights/LightCulling.h"
#include "render/lights/LightVolume.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/scene/Camera.h"
#include "tests/LightTestScenes.h"

namespace sph::render::lights {
namespace {

using test::light;

// A 4 m floor under lights in its lowest 0.4 m, seen from a camera that looks at a corner of it.
scene::LightsDesc floorVolume() {
  scene::LightsDesc d;
  d.origin = Vec3(-2.1f, -0.1f, -2.1f), d.voxelSize = 0.05f, d.voxels = {84, 12, 84};
  d.attenuation = {1.0f, 0.0f, 20.0f}, d.range = 0.15f;
  d.specular = 0.5f, d.shininess = 16, d.roomLight = 0.2f;
  return d;
}

scene::CameraDesc cornerCamera() {
  scene::CameraDesc c;
  c.position = Vec3(0.2f, 1.0f, 0.5f), c.target = Vec3(0.2f, 0.0f, 0.0f), c.fovYDegrees = 40;
  c.near = 0.05f, c.far = 20;
  return c;
}

constexpr int kWidth = 160, kHeight = 120;

// With the margin of water splats of 3 cm at a spacing of 2 cm (splat size 1.5, R 2.5 spacings),
// or none (the solids, and point splats well inside the view, lit at their centres): then only
// the light's range and the filter's reach keep the lights just outside the view.
LightView cornerView(bool splatMargin) {
  LightView v = lightView(cornerCamera(), static_cast<float>(kWidth) / kHeight, 1.5f, 2.5f, 0.02f);
  if (!splatMargin) v.margin = 0;
  return v;
}

std::vector<sph::lights::LightParticle> floorLights(std::size_t n) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<sph::lights::LightParticle> lights;
  for (std::size_t i = 0; i < n; ++i)
    lights.push_back(light(Vec3(4 * u(rng) - 2, 0.02f + 0.38f * u(rng), 4 * u(rng) - 2),
                           Vec3(1.0f, 0.4f + 0.6f * u(rng), 0.2f + 0.8f * u(rng)), 0.5f));
  return lights;
}

// The nearest frustum plane's signed distance (m, negative outside).
float insideBy(const scene::Frustum& f, const Vec3& p) {
  float d = 1e30f;
  for (int k = 0; k < 6; ++k) d = std::min(d, f.distance(k, p));
  return d;
}

Vec3 at(const sph::lights::LightParticle& l) {
  return Vec3(l.position[0], l.position[1], l.position[2]);
}

// Every voxel the filter may read at points inside the frustum (random points in the volume,
// rejected unless inside) is in the box; and the box is well under half the volume.
TEST(LightCulling, EveryVoxelAVisiblePointReadsIsInTheBox) {
  const LightView view = cornerView(false);
  const scene::Frustum frustum(view.projView);
  for (scene::LightFilter filter :
       {scene::LightFilter::Nearest, scene::LightFilter::Trilinear, scene::LightFilter::Tricubic}) {
    for (int oversampling : {1, 2}) {
      scene::LightsDesc d = floorVolume();
      d.filter = filter, d.oversampling = oversampling;
      const VoxelBox box = viewVoxels(d, view);
      ASSERT_FALSE(box.empty());
      EXPECT_LT(box.count(), d.voxelCount() * 2 / 5);
      // Per axis: the filter's reach in voxels (half a voxel, one, two; half more oversampled).
      const float reach = (filter == scene::LightFilter::Nearest     ? 0.5f
                           : filter == scene::LightFilter::Trilinear ? 1.0f
                                                                     : 2.0f) +
                          (oversampling > 1 ? 0.5f : 0.0f);
      std::mt19937 rng(7);
      std::uniform_real_distribution<float> u(0.0f, 1.0f);
      int tried = 0;
      for (int i = 0; i < 200000 && tried < 4000; ++i) {
        const Vec3 p = d.origin + d.extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        if (insideBy(frustum, p) < 0) continue;
        ++tried;
        const Vec3 g = (p - d.origin) / d.voxelSize;
        std::array<int, 3> lo{}, hi{};
        for (int a = 0; a < 3; ++a) {
          // Voxel v is read when its centre v + 1/2 is within `reach` of g.
          lo[static_cast<std::size_t>(a)] =
              std::max(0, static_cast<int>(std::ceil(g[a] - 0.5f - reach)));
          hi[static_cast<std::size_t>(a)] =
              std::min(d.voxels[static_cast<std::size_t>(a)] - 1,
                       static_cast<int>(std::floor(g[a] - 0.5f + reach)));
        }
        for (const std::array<int, 3>& v : {lo, hi})
          ASSERT_TRUE(box.contains(v))
              << nameOf(filter) << " x" << oversampling << " at " << p.transpose() << ": voxel "
              << v[0] << " " << v[1] << " " << v[2];
      }
      EXPECT_GT(tried, 1000);
    }
  }
}

// A light outside the frustum by 0.9 of its range (more than the filter's reach: its light reaches
// in) is kept; one outside by more than range + filter reach is dropped, as is one beyond every
// voxel of the box.
TEST(LightCulling, ALightJustOutsideTheViewWhoseRangeReachesInIsKept) {
  const scene::LightsDesc d = floorVolume();
  const LightView view = cornerView(false);
  ASSERT_GT(0.9f * d.range, filterReach(d));
  const scene::Frustum frustum(view.projView);
  const VoxelBox box = viewVoxels(d, view);
  // From a point on the floor in view, out through the left plane (k = 0).
  const Vec3 inside(0.2f, 0.05f, 0.0f);
  ASSERT_GT(insideBy(frustum, inside), 0.0f);
  const Vec3 out = -frustum.planes[0].head<3>();
  const float toPlane = frustum.distance(0, inside);
  const Vec3 near = inside + (toPlane + 0.9f * d.range) * out;
  const float beyond = d.range + filterReach(d) + view.margin;
  const Vec3 far = inside + (toPlane + 1.05f * beyond) * out;
  ASSERT_LT(frustum.distance(0, near), 0.0f);
  const std::vector<sph::lights::LightParticle> lights = {light(near, Vec3::Ones(), 1),
                                                          light(far, Vec3::Ones(), 1),
                                                          light(Vec3(50, 0, 0), Vec3::Ones(), 1)};
  const std::vector<sph::lights::LightParticle> kept = lightsInView(d, lights, view, box);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(at(kept[0]), near);
}

class LightsCullGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

solids::SolidRenderer floorSolids() {
  return solids::SolidRenderer(
      test::floorSphereBlock(Vec3(0.1f, 0.12f, 0.1f), 0.12f, Vec3(0.3f, 0, -0.3f),
                             Vec3(0.45f, 0.15f, -0.15f)),
      Aabb{Vec3(-2, -1, -2), Vec3(2, 1, 2)}, 0.02f);
}

frame::RenderImage draw(splat::SplatRenderer& r, const LightVolume& v) {
  splat::SplatFrame water;  // a few point splats in the middle of the view
  water.halfSize = 0.03f;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i)
      water.points.push_back(
          splat::SplatVertex{{0.05f + 0.05f * i, 0.03f, 0.2f + 0.05f * j}, {0, 1, 0}});
  frame::Lighting lighting;
  lighting.extra = &v;
  return r.render(water, splat::SplatKind::Point, cornerCamera(), lighting);
}

// The culled frame is the unculled one, byte for byte, for both pipelines and every filter,
// while it accumulates a small part of the lights and voxels; the lights just outside the view
// (within range of it) change the picture, so a culling that dropped them would fail here.
TEST_F(LightsCullGl, TheCulledPictureIsTheUnculledOne) {
  const std::vector<sph::lights::LightParticle> lights = floorLights(4000);
  const LightView view = cornerView(false);
  const scene::Frustum frustum(view.projView);
  std::vector<sph::lights::LightParticle>
      withoutEdge;  // less those outside the view but within range of it
  std::size_t edge = 0;
  for (const sph::lights::LightParticle& l : lights) {
    const float in = insideBy(frustum, at(l));
    if (in < 0 && in > -floorVolume().range)
      ++edge;
    else
      withoutEdge.push_back(l);
  }
  ASSERT_GT(edge, 10u);
  solids::SolidRenderer solids = floorSolids();
  splat::SplatRenderer r(kWidth, kHeight);
  r.setLayers({&solids});
  struct Setting {
    scene::LightFilter filter;
    int oversampling;
    scene::LightPipeline pipeline;
  };
  for (const Setting s :
       {Setting{scene::LightFilter::Trilinear, 1, scene::LightPipeline::Forward},
        Setting{scene::LightFilter::Trilinear, 1, scene::LightPipeline::Deferred},
        Setting{scene::LightFilter::Nearest, 1, scene::LightPipeline::Deferred},
        Setting{scene::LightFilter::Tricubic, 2, scene::LightPipeline::Forward}}) {
    scene::LightsDesc d = floorVolume();
    d.filter = s.filter, d.oversampling = s.oversampling, d.pipeline = s.pipeline;
    LightVolume all(d), culled(d);
    all.update(lights);
    culled.update(lights, &view);
    EXPECT_EQ(all.lastLights(), lights.size());
    EXPECT_LT(culled.lastLights(), lights.size() / 3) << "most lights are out of view";
    EXPECT_LT(culled.lastBox().count(), d.voxelCount() * 2 / 5);
    const frame::RenderImage a = draw(r, all), c = draw(r, culled);
    ASSERT_EQ(a.rgb.size(), c.rgb.size());
    EXPECT_TRUE(a.rgb == c.rgb) << nameOf(s.filter) << " x" << s.oversampling << " "
                                << nameOf(s.pipeline);
    // The lights just outside the view light it: without them the picture changes.
    LightVolume less(d);
    less.update(withoutEdge);
    const frame::RenderImage e = draw(r, less);
    int changed = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) changed += a.rgb[i] != e.rgb[i];
    EXPECT_GT(changed, 30) << nameOf(s.filter) << " " << nameOf(s.pipeline);
  }
}

// A camera that moves between frames: the voxels the last frame accumulated outside the new box
// are cleared (the new frame's outside reads zero), those the new camera sees hold the plain
// volume's values, and an unculled update after culled ones is the plain volume again.
TEST_F(LightsCullGl, AMovingCameraLeavesNoStaleVoxels) {
  const scene::LightsDesc d = floorVolume();
  const std::vector<sph::lights::LightParticle> lights = floorLights(4000);
  scene::CameraDesc other = cornerCamera();
  other.position = Vec3(-0.5f, 0.5f, -1.4f), other.target = Vec3(-0.8f, 0.0f, -0.6f);
  const LightView a = cornerView(true),
                  b = lightView(other, static_cast<float>(kWidth) / kHeight, 1.5f, 2.5f, 0.02f);
  LightVolume moving(d), plain(d);
  plain.update(lights);
  const auto expected = plain.readColour();
  moving.update(lights, &a);
  moving.update(lights, &b);
  const VoxelBox box = moving.lastBox();
  const VoxelBox boxA = viewVoxels(d, a);
  const scene::Frustum frustumB(b.projView);
  ASSERT_FALSE(box.empty());
  const auto colour = moving.readColour();
  std::size_t outsideA = 0, insideBoth = 0;
  for (int z = 0; z < d.voxels[2]; ++z)
    for (int y = 0; y < d.voxels[1]; ++y)
      for (int x = 0; x < d.voxels[0]; ++x) {
        const std::size_t i = (static_cast<std::size_t>(z) * d.voxels[1] + y) * d.voxels[0] +
                              static_cast<std::size_t>(x);
        if (box.contains({x, y, z})) {
          // Voxels whose centres the camera sees hold every light that reaches them.
          if (insideBy(frustumB, d.origin + d.voxelSize * Vec3(x + 0.5f, y + 0.5f, z + 0.5f)) < 0)
            continue;
          ASSERT_EQ(colour[i], expected[i]) << x << " " << y << " " << z;
          ++insideBoth;
        } else {
          ASSERT_EQ(colour[i][0], 0.0f) << "stale voxel " << x << " " << y << " " << z;
          outsideA += boxA.contains({x, y, z}) && expected[i][0] > 0;
        }
      }
  EXPECT_GT(outsideA, 100u) << "the first view's lit voxels were there to clear";
  EXPECT_GT(insideBoth, 1000u);
  moving.update(lights);
  EXPECT_TRUE(moving.readColour() == expected);
}

}  // namespace
}  // namespace sph::render::lights
