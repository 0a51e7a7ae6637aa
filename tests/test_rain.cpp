// The view-dependent rain's drops over time (seed 002, Im & Sung 2021; docs/rain.md): the whole
// budget kept in view where the camera-centred box and the fixed region spend it behind the
// camera, also through a pan; respawn out of solids and water, however thin the water; the union
// of an MPI run's water cells; wind; and the seed. CPU only; where a drop is placed is
// test_rain_space, the streaks test_rain_gl.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "sim/scene/Camera.h"
#include "sim/scene/Solid.h"
#include "sim/rain/RainSystem.h"
#include "tests/RainTestScenes.h"

namespace sph {
namespace {

using rain::RainSystem;
using test::fractionInView;
using test::kAspect;
using test::lookingAlongZ;
using test::rainDesc;

// The claim of the paper in numbers: the share of the budget inside the view frustum.
TEST(RainSystem, ViewKeepsTheWholeBudgetInViewTheBaselinesDoNot) {
  const scene::CameraDesc c = lookingAlongZ();
  double fraction[3];
  for (scene::RainSpawn spawn :
       {scene::RainSpawn::View, scene::RainSpawn::Box, scene::RainSpawn::Region}) {
    RainSystem r(rainDesc(spawn), kAspect);
    r.reset(c);
    for (int f = 0; f < 30; ++f) r.update(c, 1.0f / 30);
    fraction[static_cast<int>(spawn)] = fractionInView(r, c);
    if (spawn == scene::RainSpawn::View) {
      const double sphere = 4.0 / 3 * M_PI * std::pow(r.space().radius, 3.0);
      std::printf(
          "rain space %.2f m^3 of the sphere's %.2f m^3; side planes rejected %.3f of "
          "the samples\n",
          r.space().volume(), sphere,
          static_cast<double>(r.counters().rejected) /
              static_cast<double>(r.counters().rejected + r.counters().accepted));
      EXPECT_NEAR(static_cast<double>(r.counters().accepted) /
                      static_cast<double>(r.counters().rejected + r.counters().accepted),
                  r.space().volume() / sphere, 0.02);
    }
    if (spawn == scene::RainSpawn::Box) std::printf("box edge %.3f m\n", r.boxEdge());
    std::printf("spawn %-6s: %.4f of %zu drops in the frustum\n", enumName(spawn),
                fraction[static_cast<int>(spawn)], r.size());
  }
  EXPECT_EQ(fraction[0], 1.0);
  // The camera-centred box of the same volume: the camera sees only the part ahead of it.
  EXPECT_LT(fraction[1], 0.25);
  EXPECT_GT(fraction[1], 0.02);
  // The 180 m^3 region holds ~50 m^3 of the frustum (near 0.1 m to far 5 m, 4.1 x 7.4 m at far):
  // about 0.3 of the budget in view, the rest spent behind and beside the camera.
  EXPECT_GT(fraction[2], 0.2);
  EXPECT_LT(fraction[2], 0.4);
}

TEST(RainSystem, RespawnKeepsTheBudgetAndNoDropIsEverInsideASolid) {
  const scene::CameraDesc c = lookingAlongZ();
  scene::RainDesc d = rainDesc(scene::RainSpawn::View);
  d.wind = Vec3(1, 0, 0);
  scene::BoundaryShape block;
  block.kind = scene::BoundaryShape::Kind::Block;
  block.lo = Vec3(-1, -1, -1), block.hi = Vec3(1, 1, 3);  // the lower half of the rain space
  const std::vector<scene::Solid> solids = {scene::Solid(block, 0.01f)};
  rain::RainObstacles obstacles;
  obstacles.solids = &solids;
  RainSystem r(d, kAspect);
  r.reset(c, obstacles);
  for (int f = 0; f < 60; ++f) {
    r.update(c, 1.0f / 60, obstacles);
    ASSERT_EQ(r.size(), d.count);
    std::size_t inSolid = 0;
    for (const Vec3& p : r.positions()) inSolid += rain::insideSolid(p, solids);
    ASSERT_EQ(inSolid, 0u) << "frame " << f;
  }
  EXPECT_GT(r.counters().hitSolid, 1000u);
  EXPECT_GT(r.counters().leftSpace, 1000u);
  EXPECT_EQ(fractionInView(r, c), 1.0);
}

TEST(RainSystem, DropsHittingTheWaterAreRespawned) {
  const scene::CameraDesc c = lookingAlongZ();
  std::vector<Vec3> pool;  // a 2 m x 0.2 m x 2 m slab of water around y = 0.5
  for (float x = -1; x < 1; x += 0.02f)
    for (float z = 0; z < 2; z += 0.02f)
      for (float y = 0.4f; y < 0.6f; y += 0.02f) pool.emplace_back(x, y, z);
  const rain::WaterCells water(pool, 0.04f);
  rain::RainObstacles obstacles;
  obstacles.water = &water;
  RainSystem r(rainDesc(scene::RainSpawn::View), kAspect);
  r.reset(c, obstacles);
  for (int f = 0; f < 30; ++f) r.update(c, 1.0f / 60, obstacles);
  EXPECT_GT(r.counters().hitWater, 100u);
  std::size_t wet = 0;
  for (const Vec3& p : r.positions()) wet += water.contains(p);
  EXPECT_EQ(wet, 0u);
}

// A sheet of water one cell (0.04 m) thick: at 6 m/s and 30 fps a drop falls 0.2 m a step, so a
// test of where it ends alone let most drops through. The path is tested: none gets through.
TEST(RainSystem, DropsFallingThroughAThinSheetOfWaterLandInIt) {
  const scene::CameraDesc c = lookingAlongZ();
  std::vector<Vec3> sheet;  // 2 m x 2 m at y = 0.5: the cells 0.48 <= y < 0.52
  for (float x = -1; x < 1; x += 0.02f)
    for (float z = 0; z < 2; z += 0.02f) sheet.emplace_back(x, 0.5f, z);
  const rain::WaterCells water(sheet, 0.04f);
  rain::RainObstacles obstacles;
  obstacles.water = &water;
  scene::RainDesc d = rainDesc(scene::RainSpawn::View);
  ASSERT_GT(d.fallSpeed / 30, 4 * 0.04f);
  RainSystem r(d, kAspect);
  r.reset(c, obstacles);
  std::size_t through = 0;
  for (int f = 0; f < 30; ++f) {
    const std::vector<Vec3> before = r.positions();
    const std::vector<std::uint32_t> generations = r.generations();
    r.update(c, 1.0f / 30, obstacles);
    for (std::size_t i = 0; i < before.size(); ++i) {
      const Vec3& a = before[i];
      const Vec3& b = r.positions()[i];
      through += r.generations()[i] == generations[i] && a.y() >= 0.52f && b.y() < 0.48f &&
                 b.x() > -0.98f && b.x() < 0.98f && b.z() > 0.02f && b.z() < 1.98f;
    }
  }
  EXPECT_EQ(through, 0u);
  EXPECT_GT(r.counters().hitWater, 1000u);
}

// A pool whose surface is the floor of the rain space (rain_fill's region ends at its pool): a
// drop that enters the water and ends below the space in the same step landed; it did not leave.
TEST(RainSystem, ADropThatCrossesTheWaterOutOfTheRainSpaceLandsInIt) {
  const scene::CameraDesc c = lookingAlongZ();
  std::vector<Vec3> sheet;  // the cells 0.48 <= y < 0.52 over x, z in [-1, 1]
  for (float x = -1; x < 1; x += 0.02f)
    for (float z = -1; z < 1; z += 0.02f) sheet.emplace_back(x, 0.5f, z);
  const rain::WaterCells water(sheet, 0.04f);
  rain::RainObstacles obstacles;
  obstacles.water = &water;
  scene::RainDesc d = rainDesc(scene::RainSpawn::Region, 5000);
  d.wind = Vec3::Zero();
  d.region.lo = Vec3(-0.9f, 0.5f, -0.9f), d.region.hi = Vec3(0.9f, 1.5f, 0.9f);
  RainSystem r(d, kAspect);
  r.reset(c, obstacles);
  for (int f = 0; f < 60; ++f) r.update(c, 1.0f / 30, obstacles);
  EXPECT_GT(r.counters().hitWater, 5000u);
  EXPECT_EQ(r.counters().leftSpace, 0u) << "every drop leaves through the water under it";
}

TEST(RainSystem, TheUnionOfThePartsWaterCellsStopsTheDropsAsTheWholeFluidDoes) {
  // An MPI run's rank 0 steps the drops with the union of the cells its ranks' particles occupy
  // (job/distributed/CollectiveCacheSink.h): cut across x off the cell grid, so cells straddle the cuts.
  const scene::CameraDesc c = lookingAlongZ();
  std::vector<Vec3> pool;
  std::vector<std::vector<Vec3>> parts(3);
  for (float x = -1; x < 1; x += 0.02f)
    for (float z = 0; z < 2; z += 0.02f)
      for (float y = 0.4f; y < 0.6f; y += 0.02f) {
        pool.emplace_back(x, y, z);
        parts[x < -0.33f ? 0 : x < 0.35f ? 1 : 2].emplace_back(x, y, z);
      }
  const float cell = 0.04f;
  const rain::WaterCells whole(pool, cell);
  std::vector<std::uint64_t> keys;
  std::size_t withoutLast = 0;
  for (const std::vector<Vec3>& part : parts) {
    const std::vector<std::uint64_t> k = rain::WaterCells(part, cell).keys();
    for (const Vec3& p : part)
      ASSERT_TRUE(std::binary_search(k.begin(), k.end(), rain::WaterCells::keyOf(p, cell)));
    withoutLast = keys.size();
    keys.insert(keys.end(), k.begin(), k.end());
  }
  const rain::WaterCells united = rain::WaterCells::fromKeys(keys, cell);
  EXPECT_EQ(united.keys(), whole.keys());
  EXPECT_GT(keys.size(), whole.size());  // the straddling cells were sent by two parts
  keys.resize(withoutLast);              // a part missing is missed
  EXPECT_LT(rain::WaterCells::fromKeys(keys, cell).size(), whole.size());
  RainSystem a(rainDesc(scene::RainSpawn::View), kAspect),
      b(rainDesc(scene::RainSpawn::View), kAspect);
  rain::RainObstacles withWhole, withUnited;
  withWhole.water = &whole, withUnited.water = &united;
  a.reset(c, withWhole), b.reset(c, withUnited);
  for (int f = 0; f < 30; ++f)
    a.update(c, 1.0f / 60, withWhole), b.update(c, 1.0f / 60, withUnited);
  EXPECT_GT(a.counters().hitWater, 100u);
  EXPECT_EQ(a.counters().hitWater, b.counters().hitWater);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.positions().data(), b.positions().data(), a.size() * sizeof(Vec3)));
  EXPECT_EQ(a.generations(), b.generations());
}

TEST(RainSystem, DropsFallWithTheWind) {
  scene::RainDesc d = rainDesc(scene::RainSpawn::Region, 1000);
  d.wind = Vec3(2, 0, -1);
  d.fallSpeed = 5;
  RainSystem r(d, kAspect);
  r.reset(lookingAlongZ());
  const std::vector<Vec3> before = r.positions();
  r.update(lookingAlongZ(), 0.01f);
  int moved = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (((r.positions()[i] - before[i]) - Vec3(0.02f, -0.05f, -0.01f)).norm() < 1e-5f) ++moved;
  }
  EXPECT_GT(moved, 975);  // all but the ~1.5% that left the 6 x 5 x 6 m region (respawned)
}

TEST(RainSystem, AfterANinetyDegreePanEveryDropIsInTheNewViewTheBoxLosesThem) {
  scene::CameraDesc c = lookingAlongZ();
  RainSystem view(rainDesc(scene::RainSpawn::View), kAspect);
  RainSystem box(rainDesc(scene::RainSpawn::Box), kAspect);
  view.reset(c), box.reset(c);
  const scene::CameraPath pan = {{0.0, c.position, c.target, 45},
                                 {1.0, c.position, Vec3(-4, 1, 4), 45}};
  double minView = 1, minBox = 1;
  for (int f = 1; f <= 30; ++f) {
    const scene::CameraDesc now = cameraAt(c, pan, f / 30.0);
    view.update(now, 1.0f / 30), box.update(now, 1.0f / 30);
    minView = std::min(minView, fractionInView(view, now));
    minBox = std::min(minBox, fractionInView(box, now));
  }
  std::printf("during a 90-degree pan in 1 s: min in view %.4f (view), %.4f (box)\n", minView,
              minBox);
  EXPECT_EQ(minView, 1.0);
  EXPECT_LT(minBox, 0.25);
  // The drops really moved with the camera: now all on the -x side of the eye.
  for (const Vec3& p : view.positions()) ASSERT_LT(p.x(), 0.0f);
}

TEST(RainSystem, SameSeedIsBitIdenticalAnotherSeedIsNot) {
  auto run = [](std::uint64_t seed) {
    scene::RainDesc d = rainDesc(scene::RainSpawn::View, 5000);
    d.seed = seed;
    RainSystem r(d, kAspect);
    r.reset(lookingAlongZ());
    for (int f = 0; f < 20; ++f) r.update(lookingAlongZ(), 1.0f / 30);
    return r.positions();
  };
  const std::vector<Vec3> a = run(1), b = run(1), c = run(2);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)), 0);
  EXPECT_NE(std::memcmp(a.data(), c.data(), a.size() * sizeof(Vec3)), 0);
}

}  // namespace
}  // namespace sph
