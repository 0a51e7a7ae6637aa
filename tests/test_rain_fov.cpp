// Placing drops at any field of view (seed 002, docs/rain.md, "How `uniform` places a drop"): at
// a narrow fov the rain space is a thin needle of the sphere of eq. (5), and a spawn that finds no
// free place is parked at the sphere's centre. Facing empty sky and a cup of water at 3, 5 and 8
// degrees: no drop parked, and the drops placed are uniform in the rain space minus the solids
// and the water (chi-square against the volume that quadrature gives, independently of the
// sampler). CPU only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "sim/rain/RainStepper.h"
#include "sim/rain/RainSystem.h"
#include "sim/scene/Camera.h"
#include "sim/scene/Solid.h"
#include "tests/RainTestScenes.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using rain::RainSystem;

// Camera coordinates that make the frustum a cube: depth z, w = (z^3 - n^3) / (f^3 - n^3) in
// [0, 1], u = x / (z tx) and v = y / (z ty) in [-1, 1]. dx dy dz = z^2 tx ty du dv dz and
// dw = 3 z^2 dz / (f^3 - n^3), so volume in the frustum is volume in (w, u, v).
struct FrustumCube {
  rain::RainSpace s;
  float tx, ty;
  FrustumCube(const scene::CameraDesc& c, float aspect, float near, float far)
      : s(rain::RainSpace::build(c, aspect, near, far)),
        tx(scene::tanHalfFovY(c) * aspect),
        ty(scene::tanHalfFovY(c)) {}
  Vec3 point(double w, double u, double v) const {
    const double n3 = std::pow(double(s.near), 3), f3 = std::pow(double(s.far), 3);
    const double z = std::cbrt(n3 + w * (f3 - n3));
    return s.eye + float(z) * s.forward + float(u * z * tx) * s.right + float(v * z * ty) * s.up;
  }
  void coordinates(const Vec3& p, double& w, double& u, double& v) const {
    const Vec3 d = p - s.eye;
    const double z = d.dot(s.forward);
    const double n3 = std::pow(double(s.near), 3), f3 = std::pow(double(s.far), 3);
    w = (z * z * z - n3) / (f3 - n3);
    u = d.dot(s.right) / (z * tx), v = d.dot(s.up) / (z * ty);
  }
};

// Bins: 10 of depth (w) and 10 x 10 of direction (u, v).
int depthBin(double w) {
  return std::clamp(static_cast<int>(w * 10), 0, 9);
}
int directionBin(double u, double v) {
  return 10 * std::clamp(static_cast<int>((u + 1) * 5), 0, 9) +
         std::clamp(static_cast<int>((v + 1) * 5), 0, 9);
}

// Chi-square of `observed` against `expected` (shares summing to 1), over the bins expected to
// hold at least 5; degrees of freedom returned in `dof`. A drop in a bin expected empty counts
// as failing outright (infinite).
double chiSquare(const std::vector<double>& observed, const std::vector<double>& expected,
                 int& dof) {
  double total = 0, chi = 0;
  for (double o : observed) total += o;
  dof = -1;
  bool impossible = false;
  for (std::size_t b = 0; b < observed.size(); ++b) {
    const double e = expected[b] * total;
    impossible = impossible || (e == 0 && observed[b] > 0);
    if (e < 5) continue;
    chi += (observed[b] - e) * (observed[b] - e) / e, ++dof;
  }
  return impossible ? INFINITY : chi;
}

// The chi-square value a test of `dof` degrees of freedom exceeds with p = 0.001
// (Wilson-Hilferty: 28.0 for 9, where the table says 27.9; 148.7 for 99, the table 148.2).
double chiSquare999(int dof) {
  const double k = dof, a = 2 / (9 * k);
  return k * std::pow(1 - a + 3.090 * std::sqrt(a), 3);
}

struct Uniformity {
  double chiDepth, chiDirection, limitDepth, limitDirection;
};

// The drops `placed` against the volume of the rain space outside the obstacles, by a midpoint
// rule of 200 x 100 x 100 points of the frustum cube.
Uniformity uniformity(const FrustumCube& f, const std::vector<Vec3>& placed,
                      const rain::RainObstacles& obstacles) {
  std::vector<double> depthE(10, 0), dirE(100, 0), depthO(10, 0), dirO(100, 0);
  constexpr int kW = 200, kUV = 100;
  double volume = 0;
  for (int i = 0; i < kW; ++i)
    for (int j = 0; j < kUV; ++j)
      for (int k = 0; k < kUV; ++k) {
        const double w = (i + 0.5) / kW, u = (j + 0.5) / kUV * 2 - 1, v = (k + 0.5) / kUV * 2 - 1;
        const Vec3 p = f.point(w, u, v);
        if (!f.s.insideSphere(p)) continue;
        if (obstacles.solids && rain::insideSolid(p, *obstacles.solids)) continue;
        if (obstacles.water && obstacles.water->contains(p)) continue;
        depthE[depthBin(w)] += 1, dirE[directionBin(u, v)] += 1, volume += 1;
      }
  for (double& e : depthE) e /= volume;
  for (double& e : dirE) e /= volume;
  for (const Vec3& p : placed) {
    double w, u, v;
    f.coordinates(p, w, u, v);
    depthO[depthBin(w)] += 1, dirO[directionBin(u, v)] += 1;
  }
  Uniformity r;
  int dofDepth, dofDirection;
  r.chiDepth = chiSquare(depthO, depthE, dofDepth);
  r.chiDirection = chiSquare(dirO, dirE, dofDirection);
  r.limitDepth = chiSquare999(dofDepth), r.limitDirection = chiSquare999(dofDirection);
  return r;
}

// Drops exactly at the rain space's centre: where a spawn that found no free place parks one.
std::size_t atCentre(const RainSystem& r) {
  return static_cast<std::size_t>(
      std::count(r.positions().begin(), r.positions().end(), r.space().centre));
}

// `count` drops reset at `camera`, then 10 frames at 30 fps with it still: the drops placed (all
// at the reset, the respawned ones after), and the most parked at once.
struct Placed {
  std::vector<Vec3> drops;
  std::size_t mostParked = 0, count = 0;
  std::uint64_t parked = 0;  // RainCounters::parked
};
Placed placeDrops(const scene::RainDesc& d, const scene::CameraDesc& camera,
                  const rain::RainObstacles& obstacles) {
  RainSystem r(d, test::kAspect);
  r.reset(camera, obstacles);
  Placed out;
  out.count = d.count;
  out.drops = r.positions();
  out.mostParked = atCentre(r);
  for (int f = 0; f < 10; ++f) {
    const std::vector<std::uint32_t> gens = r.generations();
    r.update(camera, 1.0f / 30, obstacles);
    for (std::size_t i = 0; i < r.size(); ++i)
      if (r.generations()[i] != gens[i]) out.drops.push_back(r.positions()[i]);
    out.mostParked = std::max(out.mostParked, atCentre(r));
  }
  out.parked = r.counters().parked;
  return out;
}

TEST(RainPlacement, FacingEmptySkyAtNarrowFieldsOfViewNoDropIsParkedAndTheyAreUniform) {
  for (float fov : {3.0f, 5.0f, 8.0f}) {
    scene::CameraDesc c = test::lookingAlongZ();
    c.target = c.position + Vec3(0, 0.5f, -1);  // up into the sky
    c.fovYDegrees = fov;
    const scene::RainDesc d = test::rainDesc(scene::RainSpawn::View, 100000);
    const Placed p = placeDrops(d, c, {});
    const Uniformity u = uniformity(FrustumCube(c, test::kAspect, d.near, d.far), p.drops, {});
    std::printf(
        "fov %g: at most %.4f of the budget parked; %zu drops placed, chi2 depth %.1f (limit "
        "%.1f), direction %.1f (limit %.1f)\n",
        fov, double(p.mostParked) / double(p.count), p.drops.size(), u.chiDepth, u.limitDepth,
        u.chiDirection, u.limitDirection);
    EXPECT_EQ(p.mostParked, 0u) << "fov " << fov;
    EXPECT_EQ(p.parked, 0u) << "fov " << fov;
    EXPECT_LT(u.chiDepth, u.limitDepth) << "fov " << fov;
    EXPECT_LT(u.chiDirection, u.limitDirection) << "fov " << fov;
  }
}

// rain_pour's rain, cup and tray, the cup full of water to 8 cm, the camera aimed at the cup.
TEST(RainPlacement, AimedAtACupOfWaterAtNarrowFieldsOfViewNoDropIsParkedAndTheyAreUniform) {
  const scene::Scene scene = test::shippedScene("rain_pour");
  std::vector<scene::Solid> solids;
  for (const scene::BoundaryShape& b : scene.boundaries)
    solids.emplace_back(b, scene.solver.wallThickness());
  std::vector<Vec3> fluid;
  const float h = scene.solver.spacing;
  for (float x = -0.05f + h / 2; x < 0.05f; x += h)
    for (float z = -0.05f + h / 2; z < 0.05f; z += h)
      for (float y = h / 2; y < 0.08f; y += h)
        if (x * x + z * z < 0.05f * 0.05f) fluid.emplace_back(x, y, z);
  const rain::WaterCells water(fluid, rain::RainStepper::waterCell(scene));
  rain::RainObstacles obstacles;
  obstacles.solids = &solids, obstacles.water = &water;
  for (float fov : {3.0f, 5.0f, 8.0f}) {
    scene::CameraDesc c = *scene.camera;
    c.fovYDegrees = fov;
    scene::RainDesc d = *scene.rain;
    d.count = 100000;
    const Placed p = placeDrops(d, c, obstacles);
    const Uniformity u =
        uniformity(FrustumCube(c, test::kAspect, d.near, d.far), p.drops, obstacles);
    std::size_t blocked = 0;
    for (const Vec3& q : p.drops) blocked += rain::insideSolid(q, solids) || water.contains(q);
    std::printf(
        "cup, fov %g: at most %.4f of the budget parked; %zu drops placed, %zu in a solid or the "
        "water, chi2 depth %.1f (limit %.1f), direction %.1f (limit %.1f)\n",
        fov, double(p.mostParked) / double(p.count), p.drops.size(), blocked, u.chiDepth,
        u.limitDepth, u.chiDirection, u.limitDirection);
    EXPECT_EQ(p.mostParked, 0u) << "fov " << fov;
    EXPECT_EQ(p.parked, 0u) << "fov " << fov;
    EXPECT_EQ(blocked, 0u) << "fov " << fov;
    EXPECT_LT(u.chiDepth, u.limitDepth) << "fov " << fov;
    EXPECT_LT(u.chiDirection, u.limitDirection) << "fov " << fov;
  }
}

}  // namespace
}  // namespace sph
