// The geometry the view model's drops are placed in and lit by (seed 002, Im & Sung 2021;
// docs/rain.md): the rain space of eq. (1)-(9) against the general frustum, the spawn inside it,
// the samplers of eq. (6)-(7) and their SIMD lanes, and the spotlight cone of eq. (10)-(13). CPU
// only; the drops' motion and respawn are test_rain, the streaks test_rain_gl.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "sim/scene/Camera.h"
#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSystem.h"
#include "sim/rain/Spotlight.h"
#include "sim/rain/UnitBall.h"
#include "sim/rain/ViewSampler.h"
#include "tests/RainTestScenes.h"

namespace sph {
namespace {

using rain::RainSpace;
using rain::RainSystem;
using test::inFrustum;
using test::kAspect;
using test::lookingAlongZ;
using test::rainDesc;

TEST(RainSpace, SphereOfEquation5TouchesNearAndFarAndSidesAgreeWithTheFrustum) {
  const scene::CameraDesc c = lookingAlongZ();
  const RainSpace s = RainSpace::build(c, kAspect, 0.1f, 5);
  EXPECT_NEAR(s.radius, 2.45f, 1e-5f);
  EXPECT_NEAR((s.centre - Vec3(0, 1, 4 - 2.55f)).norm(), 0, 1e-5f);
  // The four side planes against Gribb-Hartmann's planes of the same camera on 10^6 points of
  // the sphere's bounding box: they must disagree only within a hair of a plane.
  scene::RainDesc d;
  const scene::Frustum f = scene::viewFrustum(c, kAspect, d.near, d.far);
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
  for (scene::RainSampling sampling : {scene::RainSampling::Uniform, scene::RainSampling::Paper}) {
    scene::RainDesc d = rainDesc(scene::RainSpawn::View, 1000000);
    d.sampling = sampling;
    RainSystem r(d, kAspect);
    r.reset(lookingAlongZ());
    const scene::Frustum f = scene::viewFrustum(lookingAlongZ(), kAspect, d.near, d.far);
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
BallStatistics ballStatistics(scene::RainSampling sampling, int n) {
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
  const BallStatistics uniform = ballStatistics(scene::RainSampling::Uniform, 200000);
  const BallStatistics paper = ballStatistics(scene::RainSampling::Paper, 200000);
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
    scene::CameraDesc c = lookingAlongZ();
    const double a = f / 30.0 * M_PI / 2;
    c.target =
        c.position + Vec3(static_cast<float>(-std::sin(a)), 0.1f, static_cast<float>(-std::cos(a)));
    spaces.push_back(RainSpace::build(c, kAspect, 0.1f, 5));
  }
  for (float fov : {10.0f, 120.0f}) {
    scene::CameraDesc c = lookingAlongZ();
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

// A `uniform` view drop is the first candidate inside the rain space, whichever way the build
// computes them, and the counters count the candidates before it: at 45 degrees the cube's
// (draws 1, 2, ...), at 10 degrees the pyramid's (draws 1 + 2t and 2 + 2t).
TEST(RainSampling, AUniformViewDropIsTheFirstCandidateInsideTheRainSpace) {
  for (float fov : {45.0f, 10.0f}) {
    scene::RainDesc d = rainDesc(scene::RainSpawn::View, 20000);
    d.seed = 99;
    scene::CameraDesc camera = lookingAlongZ();
    camera.fovYDegrees = fov;
    RainSystem r(d, kAspect);
    r.reset(camera);
    ASSERT_EQ(r.space().drawsFromPyramid(), fov < 30) << fov;
    std::uint64_t before = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const rain::DropRandom u(d.seed, i, 0);
      for (std::uint64_t t = 0;; ++t) {
        const rain::ViewCandidate c =
            r.space().drawsFromPyramid()
                ? rain::pyramidCandidate(r.space(), u.bits(1 + 2 * t), u.bits(2 + 2 * t))
                : rain::viewCandidate(r.space(), u.bits(1 + t));
        ASSERT_EQ(c.inside, r.space().contains(c.p));
        if (!c.inside) continue;
        ASSERT_EQ(std::memcmp(c.p.data(), r.positions()[i].data(), sizeof(Vec3)), 0) << i;
        before += t;
        break;
      }
    }
    const rain::RainCounters& c = r.counters();
    EXPECT_EQ(c.rejected + c.outsideSphere, before);
    EXPECT_EQ(c.parked, 0u);
    const double perDrop = static_cast<double>(before + r.size()) / static_cast<double>(r.size());
    std::printf("fov %g: candidates per drop %.3f, of them in the sphere %.3f\n", fov, perDrop,
                static_cast<double>(c.rejected + r.size()) / static_cast<double>(r.size()));
    // At 45 degrees, 16:9: the sphere holds pi/6 of the cube and the rain space 0.48 of the
    // sphere (RainSystem.ViewKeepsTheWholeBudgetInViewTheBaselinesDoNot): ~4 candidates a drop.
    // At 10 degrees the rain space is nearly all the pyramid from 0.1 m to 5 m: the sphere cuts
    // the far corners.
    const double expected = r.space().drawsFromPyramid()
                                ? r.space().pyramidVolume() / r.space().volume()
                                : 1 / (M_PI / 6 * 0.478);
    EXPECT_NEAR(perDrop, expected, 0.1) << fov;
  }
}

// eq. (10)-(13) against the plain angle test: inside the cone when the angle between p - apex and
// D is at most atan(base radius / height) and 0 <= (p - apex).D <= height.
TEST(Spotlight, ConeClassificationAgreesWithTheAngleTestOnAMillionPoints) {
  scene::SpotlightDesc l;
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

}  // namespace
}  // namespace sph
