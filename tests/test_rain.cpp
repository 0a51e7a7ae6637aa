// View-dependent rain (seed 002, Im & Sung 2021; docs/rain.md): the rain space of eq. (1)-(9),
// the samplers of eq. (6)-(7), the three spawn models, respawn, the spotlight cone of
// eq. (10)-(13), the camera path and the scene keys. CPU only; the streaks are drawn in
// test_rain_gl.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "io/scene/SceneLoader.h"
#include "sim/scene/Camera.h"
#include "sim/scene/Solid.h"
#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSystem.h"
#include "sim/rain/Spotlight.h"
#include "sim/rain/UnitBall.h"
#include "sim/rain/ViewSampler.h"

namespace sph {
namespace {

using rain::RainSpace;
using rain::RainSystem;

constexpr float kAspect = 16.0f / 9.0f;

CameraDesc lookingAlongZ() {
  CameraDesc c;
  c.position = Vec3(0, 1, 4);
  c.target = Vec3(0, 1, 0);
  c.fovYDegrees = 45;
  return c;
}

RainDesc rainDesc(RainSpawn spawn, std::size_t count = 20000) {
  RainDesc d;
  d.count = count;
  d.near = 0.1f;
  d.far = 5;
  d.spawn = spawn;
  d.region.lo = Vec3(-3, -1, -3), d.region.hi = Vec3(3, 4, 3);
  return d;
}

// The frustum of the rain camera, from the general camera maths (sim/scene/Camera.h, not RainSpace).
Frustum rainFrustum(const CameraDesc& camera, const RainDesc& d) {
  CameraDesc c = camera;
  c.near = d.near, c.far = d.far;
  return Frustum(cameraFrame(c, kAspect).projView);
}

bool inFrustum(const Frustum& f, const Vec3& p) {
  for (int k = 0; k < 6; ++k) {
    if (f.distance(k, p) < -1e-4f) return false;
  }
  return true;
}

double fractionInView(const RainSystem& r, const CameraDesc& camera) {
  const Frustum f = rainFrustum(camera, r.desc());
  std::size_t in = 0;
  for (const Vec3& p : r.positions()) in += inFrustum(f, p);
  return static_cast<double>(in) / static_cast<double>(r.size());
}

TEST(RainSpace, SphereOfEquation5TouchesNearAndFarAndSidesAgreeWithTheFrustum) {
  const CameraDesc c = lookingAlongZ();
  const RainSpace s = RainSpace::build(c, kAspect, 0.1f, 5);
  EXPECT_NEAR(s.radius, 2.45f, 1e-5f);
  EXPECT_NEAR((s.centre - Vec3(0, 1, 4 - 2.55f)).norm(), 0, 1e-5f);
  // The four side planes against Gribb-Hartmann's planes of the same camera on 10^6 points of
  // the sphere's bounding box: they must disagree only within a hair of a plane.
  RainDesc d;
  const Frustum f = rainFrustum(c, d);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  int disagree = 0, inside = 0;
  for (int i = 0; i < 1000000; ++i) {
    const Vec3 p = s.centre + s.radius * Vec3(u(rng), u(rng), u(rng));
    bool sides = true;
    float nearest = 1e9f;
    for (int k = 0; k < 4; ++k) {
      sides = sides && f.distance(k, p) >= 0;
      nearest = std::min(nearest, std::abs(f.distance(k, p)));
    }
    inside += s.insideSides(p);
    if (sides != s.insideSides(p) && nearest > 1e-5f) ++disagree;
  }
  EXPECT_EQ(disagree, 0);
  EXPECT_GT(inside, 100000);  // the test saw both sides
}

TEST(RainSystem, ViewSpawnsAMillionDropsAllInsideFrustumAndSphere) {
  for (RainSampling sampling : {RainSampling::Uniform, RainSampling::Paper}) {
    RainDesc d = rainDesc(RainSpawn::View, 1000000);
    d.sampling = sampling;
    RainSystem r(d, kAspect);
    r.reset(lookingAlongZ());
    const Frustum f = rainFrustum(lookingAlongZ(), d);
    std::size_t outFrustum = 0, outSphere = 0;
    for (const Vec3& p : r.positions()) {
      outFrustum += !inFrustum(f, p);
      outSphere += (p - r.space().centre).norm() > r.space().radius * (1 + 1e-6f);
    }
    EXPECT_EQ(outFrustum, 0u) << enumName(sampling);
    EXPECT_EQ(outSphere, 0u) << enumName(sampling);
    EXPECT_EQ(r.size(), 1000000u);
  }
}

// The claim of the paper in numbers: the share of the budget inside the view frustum.
TEST(RainSystem, ViewKeepsTheWholeBudgetInViewTheBaselinesDoNot) {
  const CameraDesc c = lookingAlongZ();
  double fraction[3];
  for (RainSpawn spawn : {RainSpawn::View, RainSpawn::Box, RainSpawn::Region}) {
    RainSystem r(rainDesc(spawn), kAspect);
    r.reset(c);
    for (int f = 0; f < 30; ++f) r.update(c, 1.0f / 30);
    fraction[static_cast<int>(spawn)] = fractionInView(r, c);
    if (spawn == RainSpawn::View) {
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
    if (spawn == RainSpawn::Box) std::printf("box edge %.3f m\n", r.boxEdge());
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

double chiSquare(const std::vector<int>& bins) {
  double total = 0, chi = 0;
  for (int b : bins) total += b;
  const double expected = total / static_cast<double>(bins.size());
  for (int b : bins) chi += (b - expected) * (b - expected) / expected;
  return chi;
}

struct BallStatistics {
  double chiRadius = 0, chiDirection = 0, innerHalf = 0;
};

// N points of the unit ball, `uniform` as the view spawn takes them (the cube's points inside the
// ball, ViewSampler.h), `paper` eq. (6)-(7), against the uniform ball: the fraction within radius
// r is r^3, so r^3 binned in 10 equal bins is flat (9 dof); so is cos(phi) x theta in 10 x 10
// bins (99 dof); and the share within r/2 is 1/8.
BallStatistics ballStatistics(RainSampling sampling, int n) {
  std::vector<int> radial(10, 0), angular(100, 0);
  int inner = 0;
  std::uint64_t draw = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 b = rain::unitBallPoint(sampling, 3, static_cast<std::uint64_t>(i), draw);
    const float r = b.norm();
    EXPECT_LE(r, 1.0f + 1e-6f);
    ++radial[std::min(9, static_cast<int>(r * r * r * 10))];
    inner += r < 0.5f;
    const double cosPhi = std::clamp(static_cast<double>(b.z()) / r, -1.0, 1.0);
    const double theta = std::atan2(b.y(), b.x()) + M_PI;
    ++angular[10 * std::min(9, static_cast<int>(5 * (cosPhi + 1))) +
              std::min(9, static_cast<int>(10 * theta / (2 * M_PI)))];
  }
  BallStatistics s;
  s.chiRadius = chiSquare(radial), s.chiDirection = chiSquare(angular);
  s.innerHalf = static_cast<double>(inner) / n;
  return s;
}

TEST(RainSampling, UniformFillsTheBallEvenlyEquation7DoesNot) {
  const BallStatistics uniform = ballStatistics(RainSampling::Uniform, 200000);
  const BallStatistics paper = ballStatistics(RainSampling::Paper, 200000);
  std::printf(
      "chi2 radius (9 dof): uniform %.1f, paper %.1f; direction (99 dof): %.1f, %.1f; share "
      "within r/2: %.4f vs %.4f\n",
      uniform.chiRadius, paper.chiRadius, uniform.chiDirection, paper.chiDirection,
      uniform.innerHalf, paper.innerHalf);
  EXPECT_LT(uniform.chiRadius, 27.9);      // p = 0.001 for 9 degrees of freedom
  EXPECT_LT(uniform.chiDirection, 148.2);  // p = 0.001 for 99
  EXPECT_GT(paper.chiRadius, 1000.0);
  EXPECT_GT(paper.chiDirection, 1000.0);
  EXPECT_NEAR(uniform.innerHalf, 0.125, 0.005);  // (1/2)^3 of the volume
  EXPECT_GT(paper.innerHalf, 0.4);               // eq. (7) piles drops near the centre
}

// The cameras of a 90-degree pan (bench_rain's) and a narrow and a wide still one.
std::vector<RainSpace> someRainSpaces() {
  std::vector<RainSpace> spaces;
  for (int f = 0; f < 30; f += 7) {
    CameraDesc c = lookingAlongZ();
    const double a = f / 30.0 * M_PI / 2;
    c.target =
        c.position + Vec3(static_cast<float>(-std::sin(a)), 0.1f, static_cast<float>(-std::cos(a)));
    spaces.push_back(RainSpace::build(c, kAspect, 0.1f, 5));
  }
  for (float fov : {10.0f, 120.0f}) {
    CameraDesc c = lookingAlongZ();
    c.fovYDegrees = fov;
    spaces.push_back(RainSpace::build(c, kAspect, 0.05f, 0.6f));
  }
  // The same side planes through points 100 km away along the frustum's edges (ntr lies on R and
  // T, nbl on L and B): nearly the same space, but (p - ntr).R sums products of ~100 km, whose
  // roundings decide the sign of many more candidates - where a sum rounded otherwise shows.
  for (std::size_t k = 0; k < 2; ++k) {
    RainSpace far = spaces[k];
    far.ntr += 1e5f * far.R.cross(far.T).normalized();
    far.nbl -= 1e5f * far.L.cross(far.B).normalized();
    spaces.push_back(far);
  }
  return spaces;
}

// The 16 candidates computed at once (AVX-512 lanes where the build has them) are, bit for bit,
// the ones computed one at a time, and their masks are RainSpace's own tests of those points: a
// drop does not depend on the machine's vector width. Fails if the side planes' sums are rounded
// otherwise in the lanes (tried: their y and z products summed with a plain add, which GCC fuses
// the other way round: 194 of the 2,880,000 masks differ, all of the spaces 100 km below).
TEST(RainSampling, CandidatesInSimdLanesAreTheOnesOneAtATime) {
  std::printf("viewCandidates16 in AVX-512 lanes: %s\n",
              rain::kViewCandidatesInLanes ? "yes" : "no");
  std::size_t inside = 0, inSphere = 0, total = 0, masks = 0, tests = 0;
  for (const RainSpace& s : someRainSpaces()) {
    for (std::uint64_t drop = 0; drop < 20000; ++drop) {
      const rain::DropRandom u(11, drop, drop % 7);
      const std::uint64_t first = 1 + 16 * (drop % 3);
      rain::ViewCandidates16 c;
      rain::viewCandidates16(s, u, first, c);
      for (unsigned k = 0; k < 16; ++k) {
        const rain::ViewCandidate one = rain::viewCandidate(s, u.bits(first + k));
        const Vec3 lane(c.x[k], c.y[k], c.z[k]);
        ASSERT_EQ(std::memcmp(lane.data(), one.p.data(), sizeof(Vec3)), 0) << drop << " " << k;
        masks += ((c.inSphere >> k) & 1) != one.inSphere || ((c.inside >> k) & 1) != one.inside;
        tests += one.inSphere != s.insideSphere(one.p) || one.inside != s.contains(one.p);
        inside += one.inside, inSphere += one.inSphere, ++total;
      }
      ASSERT_EQ(c.inSphere >> 16, 0u);
    }
  }
  EXPECT_EQ(masks, 0u) << "of " << total << " candidates: lanes against one at a time";
  EXPECT_EQ(tests, 0u) << "of " << total << " candidates: against RainSpace's tests";
  // The sphere holds pi/6 of its cube.
  EXPECT_NEAR(static_cast<double>(inSphere) / static_cast<double>(total), M_PI / 6, 0.002);
  EXPECT_GT(inside, total / 20);
  EXPECT_LT(inside, inSphere);
}

// A `uniform` view drop is the first candidate (draws 1, 2, ... of its numbers) inside the rain
// space, whichever way the build computes them, and the counters count the candidates before it.
TEST(RainSampling, AUniformViewDropIsTheFirstCandidateInsideTheRainSpace) {
  RainDesc d = rainDesc(RainSpawn::View, 20000);
  d.seed = 99;
  RainSystem r(d, kAspect);
  r.reset(lookingAlongZ());
  std::uint64_t before = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const rain::DropRandom u(d.seed, i, 0);
    for (std::uint64_t t = 0;; ++t) {
      const rain::ViewCandidate c = rain::viewCandidate(r.space(), u.bits(1 + t));
      if (!c.inside) continue;
      ASSERT_EQ(std::memcmp(c.p.data(), r.positions()[i].data(), sizeof(Vec3)), 0) << i;
      before += t;
      break;
    }
  }
  const rain::RainCounters& c = r.counters();
  EXPECT_EQ(c.rejected + c.outsideSphere, before);
  // At 45 degrees, 16:9: the sphere holds pi/6 of the cube and the rain space 0.48 of the sphere
  // (RainSystem.ViewKeepsTheWholeBudgetInViewTheBaselinesDoNot): ~4 candidates a drop.
  const double perDrop = static_cast<double>(before + r.size()) / static_cast<double>(r.size());
  std::printf("candidates per drop %.3f, of them in the sphere %.3f\n", perDrop,
              static_cast<double>(c.rejected + r.size()) / static_cast<double>(r.size()));
  EXPECT_NEAR(perDrop, 1 / (M_PI / 6 * 0.478), 0.1);
}

TEST(RainSystem, RespawnKeepsTheBudgetAndNoDropIsEverInsideASolid) {
  const CameraDesc c = lookingAlongZ();
  RainDesc d = rainDesc(RainSpawn::View);
  d.wind = Vec3(1, 0, 0);
  BoundaryShape block;
  block.kind = BoundaryShape::Kind::Block;
  block.lo = Vec3(-1, -1, -1), block.hi = Vec3(1, 1, 3);  // the lower half of the rain space
  const std::vector<Solid> solids = {Solid(block, 0.01f)};
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
  const CameraDesc c = lookingAlongZ();
  std::vector<Vec3> pool;  // a 2 m x 0.2 m x 2 m slab of water around y = 0.5
  for (float x = -1; x < 1; x += 0.02f)
    for (float z = 0; z < 2; z += 0.02f)
      for (float y = 0.4f; y < 0.6f; y += 0.02f) pool.emplace_back(x, y, z);
  const rain::WaterCells water(pool, 0.04f);
  rain::RainObstacles obstacles;
  obstacles.water = &water;
  RainSystem r(rainDesc(RainSpawn::View), kAspect);
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
  const CameraDesc c = lookingAlongZ();
  std::vector<Vec3> sheet;  // 2 m x 2 m at y = 0.5: the cells 0.48 <= y < 0.52
  for (float x = -1; x < 1; x += 0.02f)
    for (float z = 0; z < 2; z += 0.02f) sheet.emplace_back(x, 0.5f, z);
  const rain::WaterCells water(sheet, 0.04f);
  rain::RainObstacles obstacles;
  obstacles.water = &water;
  RainDesc d = rainDesc(RainSpawn::View);
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
  const CameraDesc c = lookingAlongZ();
  std::vector<Vec3> sheet;  // the cells 0.48 <= y < 0.52 over x, z in [-1, 1]
  for (float x = -1; x < 1; x += 0.02f)
    for (float z = -1; z < 1; z += 0.02f) sheet.emplace_back(x, 0.5f, z);
  const rain::WaterCells water(sheet, 0.04f);
  rain::RainObstacles obstacles;
  obstacles.water = &water;
  RainDesc d = rainDesc(RainSpawn::Region, 5000);
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
  // (app/CollectiveCacheSink.h): cut across x off the cell grid, so cells straddle the cuts.
  const CameraDesc c = lookingAlongZ();
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
  RainSystem a(rainDesc(RainSpawn::View), kAspect), b(rainDesc(RainSpawn::View), kAspect);
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
  RainDesc d = rainDesc(RainSpawn::Region, 1000);
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
  CameraDesc c = lookingAlongZ();
  RainSystem view(rainDesc(RainSpawn::View), kAspect);
  RainSystem box(rainDesc(RainSpawn::Box), kAspect);
  view.reset(c), box.reset(c);
  const CameraPath pan = {{0.0, c.position, c.target, 45}, {1.0, c.position, Vec3(-4, 1, 4), 45}};
  double minView = 1, minBox = 1;
  for (int f = 1; f <= 30; ++f) {
    const CameraDesc now = cameraAt(c, pan, f / 30.0);
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
    RainDesc d = rainDesc(RainSpawn::View, 5000);
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

// eq. (10)-(13) against the plain angle test: inside the cone when the angle between p - apex and
// D is at most atan(base radius / height) and 0 <= (p - apex).D <= height.
TEST(Spotlight, ConeClassificationAgreesWithTheAngleTestOnAMillionPoints) {
  SpotlightDesc l;
  l.position = Vec3(0.3f, 2, -0.2f);
  l.direction = Vec3(0.3f, -1, 0.1f).normalized();
  l.height = 2.5f;
  l.baseRadius = 0.8f;
  const float halfAngle = std::atan(l.baseRadius / l.height);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-3, 3);
  int inside = 0, disagree = 0;
  for (int i = 0; i < 1000000; ++i) {
    const Vec3 p = l.position + Vec3(u(rng), u(rng), u(rng));
    const Vec3 ps = p - l.position;
    const float along = ps.dot(l.direction);
    const float angle = std::acos(std::clamp(along / ps.norm(), -1.0f, 1.0f));
    const bool analytic = along >= 0 && along <= l.height && angle <= halfAngle;
    const bool ours = rain::spotlightWeight(l, p) == 1.0f;
    inside += analytic;
    if (analytic != ours && std::abs(angle - halfAngle) > 1e-4f) ++disagree;
  }
  EXPECT_EQ(disagree, 0);
  EXPECT_GT(inside, 5000);
  // Above the light (behind the apex) and past the height: no light, as in section 3.2.1.
  EXPECT_EQ(rain::spotlightWeight(l, l.position - 0.1f * l.direction), 0.0f);
  EXPECT_EQ(rain::spotlightWeight(l, l.position + 2.6f * l.direction), 0.0f);
  // A soft edge keeps the core lit, fades at the rim.
  l.softEdge = 0.5f;
  const Vec3 side = l.direction.cross(Vec3::UnitX()).normalized();
  const Vec3 mid = l.position + 2 * l.direction;  // cone radius 0.64 there
  EXPECT_EQ(rain::spotlightWeight(l, mid + 0.2f * side), 1.0f);
  EXPECT_NEAR(rain::spotlightWeight(l, mid + 0.48f * side), 0.5f, 1e-3f);
  EXPECT_EQ(rain::spotlightWeight(l, mid + 0.65f * side), 0.0f);
}

TEST(CameraPath, InterpolatesPoseAndFovAndTurnsEvenly) {
  CameraDesc base = lookingAlongZ();
  const CameraPath path = {{0.5, Vec3(0, 1, 4), Vec3(0, 1, 0), 40},
                           {1.5, Vec3(2, 1, 4), Vec3(-2, 1, 4), 60}};
  // Before and after the keys: the end keys.
  EXPECT_EQ(cameraAt(base, path, 0).target, Vec3(0, 1, 0));
  EXPECT_EQ(cameraAt(base, path, 9).position, Vec3(2, 1, 4));
  EXPECT_EQ(cameraAt(base, path, 9).fovYDegrees, 60.0f);
  // Halfway: eye and fov linear, direction turned by half of the 90 degrees.
  const CameraDesc mid = cameraAt(base, path, 1.0);
  EXPECT_NEAR((mid.position - Vec3(1, 1, 4)).norm(), 0, 1e-6f);
  EXPECT_FLOAT_EQ(mid.fovYDegrees, 50);
  const Vec3 dir = (mid.target - mid.position).normalized();
  EXPECT_NEAR(dir.dot(Vec3(0, 0, -1)), std::cos(M_PI / 4), 1e-6);
  EXPECT_NEAR(dir.dot(Vec3(-1, 0, 0)), std::cos(M_PI / 4), 1e-6);
  EXPECT_NEAR((mid.target - mid.position).norm(), 4, 1e-5);
  // A quarter of the way: a quarter of the turn.
  const CameraDesc q = cameraAt(base, path, 0.75);
  EXPECT_NEAR((q.target - q.position).normalized().dot(Vec3(0, 0, -1)), std::cos(M_PI / 8), 1e-6);
  // No path: the base camera.
  EXPECT_EQ(cameraAt(base, {}, 3).position, base.position);
}

std::string errorOf(const std::string& rain, const std::string& camera = "") {
  const std::string text = R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
    "camera": {"position": [0, 0, 1], "target": [0, 0, 0])" +
                           camera + R"(}, "rain": )" + rain + "}";
  try {
    io::parseScene(text, "r.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RainScene, KeysAreReadAndBadValuesRefusedWithOneLine) {
  const std::string text = R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
    "camera": {"position": [0, 0, 1], "target": [0, 0, 0],
               "path": [{"time": 0}, {"time": 2, "target": [1, 0, 1], "fov": 30}]},
    "rain": {"count": 500, "near": 0.2, "far": 8, "fall_speed": 4, "wind": [1, 0, 0],
             "exposure": 0.02, "seed": 9, "spawn": "region", "sampling": "paper", "lod_width": 0.5,
             "far_tier": "sums",
             "region": {"min": [-1, -1, -1], "max": [1, 1, 1]},
             "spotlight": {"position": [0, 2, 0], "colour": [1, 0, 0], "intensity": 2}}})";
  const Scene s = io::parseScene(text, "r.json");
  ASSERT_TRUE(s.rain.has_value());
  EXPECT_EQ(s.rain->count, 500u);
  EXPECT_EQ(s.rain->far, 8.0f);
  EXPECT_EQ(s.rain->spawn, RainSpawn::Region);
  EXPECT_EQ(s.rain->sampling, RainSampling::Paper);
  EXPECT_EQ(s.rain->seed, 9u);
  EXPECT_EQ(s.rain->lodWidth, 0.5f);
  EXPECT_EQ(s.rain->farTier, RainFarTier::Sums);
  ASSERT_TRUE(s.rain->spotlight.has_value());
  EXPECT_EQ(s.rain->spotlight->colour, Vec3(1, 0, 0));
  ASSERT_EQ(s.cameraPath.size(), 2u);
  EXPECT_EQ(s.cameraPath[0].position, Vec3(0, 0, 1));  // keys default to the camera's pose
  EXPECT_EQ(s.cameraPath[1].fovYDegrees, 30.0f);
  EXPECT_FALSE(io::parseScene(R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}]})",
                              "r.json")
                   .rain.has_value());

  struct Bad {
    const char* rain;
    const char* expect;
  };
  for (const Bad& b : std::initializer_list<Bad>{
           {R"({"near": 2, "far": 1})", "r.json: rain.far: expected far > near"},
           {R"({"count": 0})", "r.json: rain.count: expected an integer in [1, 1e8]"},
           {R"({"count": 1e12})", "r.json: rain.count: expected an integer in [1, 1e8]"},
           {R"({"spawn": "sky"})", "r.json: rain.spawn:"},
           {R"({"sampling": "gauss"})", "r.json: rain.sampling:"},
           {R"({"spawn": "region"})", "r.json: rain.region: missing"},
           {R"({"region": {"min": [0,0,0], "max": [1,1,1]}})", "r.json: rain.region: only used"},
           {R"({"fall_speed": -1})", "r.json: rain.fall_speed:"},
           {R"({"spotlight": {"position": [0, 1, 0], "base_radius": 0}})",
            "r.json: rain.spotlight.base_radius:"},
           {R"({"spotlight": {"position": [0, 1, 0], "colour": [2, 0, 0]}})",
            "r.json: rain.spotlight.colour:"},
           {R"({"lod_width": 1.5})", "r.json: rain.lod_width: expected a number in [0, 1]"},
           {R"({"lod_width": 0.5, "draw": "triangles"})", "r.json: rain.lod_width: only used"},
           {R"({"lod_width": 1, "far_tier": "slabs"})", "r.json: rain.far_tier:"},
           {R"({"far_tier": "sums"})", "r.json: rain.far_tier: only used with a \"lod_width\" > 0"},
           {R"({"far_tier": "sums", "lod_width": 9})",
            "r.json: rain.lod_width: expected a number in [0, 8] with \"far_tier\": \"sums\""},
           {R"({"far_tier": "lines", "lod_width": 2})",
            "r.json: rain.lod_width: expected a number in [0, 1]"},
           {R"({"raincount": 5})", "r.json: rain.raincount: unknown key"},
       }) {
    const std::string e = errorOf(b.rain);
    EXPECT_NE(e.find(b.expect), std::string::npos) << b.rain << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  EXPECT_NE(errorOf("{}", R"(, "path": [{"time": 1}, {"time": 1}])")
                .find("r.json: camera.path[1].time: expected a time after"),
            std::string::npos);
}

}  // namespace
}  // namespace sph
