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

#include "sim/rain/EyeDepth.h"
#include "sim/rain/RainRandom.h"
#include "sim/rain/RainStepper.h"
#include "sim/rain/RainSystem.h"
#include "sim/scene/Camera.h"
#include "sim/scene/Solid.h"
#include "tests/RainSight.h"
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

// The chi-square of the drops in the depth and direction bins (`depthO`, `dirO`) against the
// volumes the bins hold (`depthE`, `dirE`, summing to `volume` each).
Uniformity againstVolumes(const std::vector<double>& depthO, std::vector<double> depthE,
                          const std::vector<double>& dirO, std::vector<double> dirE,
                          double volume) {
  for (double& e : depthE) e /= volume;
  for (double& e : dirE) e /= volume;
  Uniformity r;
  int dofDepth, dofDirection;
  r.chiDepth = chiSquare(depthO, depthE, dofDepth);
  r.chiDirection = chiSquare(dirO, dirE, dofDirection);
  r.limitDepth = chiSquare999(dofDepth), r.limitDirection = chiSquare999(dofDirection);
  return r;
}

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
  for (const Vec3& p : placed) {
    double w, u, v;
    f.coordinates(p, w, u, v);
    depthO[depthBin(w)] += 1, dirO[directionBin(u, v)] += 1;
  }
  return againstVolumes(depthO, depthE, dirO, dirE, volume);
}

// The drops `placed` against the volume of the part of the rain space that the rain's depth image
// (sim/rain/EyeDepth.h) calls visible: a ray through the frustum is kept from where it enters the
// sphere (or near) to the first of where it leaves it and the image's depth at its pixel, exactly,
// since the image is one depth a pixel; 2,048 / rows rays a pixel each way weigh the pixels
// exactly and the direction bins to 1/2,048 of the field of view (1/1,024 put chi-square 130-140
// on the direction of drops that fit 1/2,048's 95-110). How far that region is from what the
// geometry lets the eye see is `imageAgainstGeometry`. Depth bins: 10 over the w the image sees to.
Uniformity imageUniformity(const FrustumCube& f, const std::vector<Vec3>& placed,
                           const rain::EyeDepth& image) {
  const rain::RainSpace& s = f.s;
  const double n3 = std::pow(double(s.near), 3), f3 = std::pow(double(s.far), 3);
  auto wOf = [&](double z) { return (z * z * z - n3) / (f3 - n3); };
  const int cols = image.cols(), rows = image.rows(), sub = 2048 / rows;
  struct Stretch {
    double w0, w1;
    int bin;
  };
  std::vector<Stretch> stretches;
  double wTop = 0;
  const Vec3 oc = s.eye - s.centre;
  for (int j = 0; j < rows * sub; ++j)
    for (int i = 0; i < cols * sub; ++i) {
      const double u = (i + 0.5) / (cols * sub) * 2 - 1, v = (j + 0.5) / (rows * sub) * 2 - 1;
      const Vec3 dir = s.forward + float(u * f.tx) * s.right + float(v * f.ty) * s.up;  // z = 1
      // The sphere along the ray: |eye + z dir - centre|^2 <= r^2.
      const double a = dir.squaredNorm(), b = 2 * oc.dot(dir);
      const double disc = b * b - 4 * a * (oc.squaredNorm() - double(s.radius) * s.radius);
      if (disc <= 0) continue;
      const double z0 = std::max<double>(s.near, (-b - std::sqrt(disc)) / (2 * a));
      const double z1 = std::min<double>((-b + std::sqrt(disc)) / (2 * a),
                                         image.depths()[std::size_t(j / sub) * cols + i / sub]);
      if (z1 <= z0) continue;
      stretches.push_back({wOf(z0), wOf(z1), directionBin(u, v)});
      wTop = std::max(wTop, wOf(z1));
    }
  std::vector<double> depthE(10, 0), dirE(100, 0), depthO(10, 0), dirO(100, 0);
  double volume = 0;
  for (const Stretch& t : stretches) {
    dirE[t.bin] += t.w1 - t.w0, volume += t.w1 - t.w0;
    for (int b = 0; b < 10; ++b) {
      const double lo = std::max(t.w0, wTop * b / 10), hi = std::min(t.w1, wTop * (b + 1) / 10);
      if (hi > lo) depthE[b] += hi - lo;
    }
  }
  for (const Vec3& p : placed) {
    double w, u, v;
    f.coordinates(p, w, u, v);
    depthO[std::clamp(static_cast<int>(w / wTop * 10), 0, 9)] += 1, dirO[directionBin(u, v)] += 1;
  }
  return againstVolumes(depthO, depthE, dirO, dirE, volume);
}

// The depth image's visible region against the geometry's (tests/RainSight.h), by 100,000 points
// uniform in the rain space outside the solids and the water cells: the share of the points the
// geometry sees that the image hides (the price of its being on the side of hiding), and of those
// the image sees that the geometry hides.
struct ImageAgainstGeometry {
  double hiddenButSeen = 0, seenButHidden = 0;
};
ImageAgainstGeometry imageAgainstGeometry(const rain::RainSpace& s, const rain::EyeDepth& image,
                                          const test::EyeSight& sight,
                                          const rain::RainObstacles& obstacles) {
  std::size_t seen = 0, imageSeen = 0, hiddenButSeen = 0, seenButHidden = 0;
  for (std::uint64_t i = 0, n = 0; n < 100000; ++i) {
    const Vec3 p = s.centre + s.radius * Vec3(2 * rain::unitRandom(7, i, 0, 0) - 1,
                                              2 * rain::unitRandom(7, i, 0, 1) - 1,
                                              2 * rain::unitRandom(7, i, 0, 2) - 1);
    if (!s.contains(p) || rain::insideSolid(p, *obstacles.solids) || obstacles.water->contains(p))
      continue;
    ++n;
    const bool truth = sight.visible(s.eye, p), byImage = image.visible(p);
    seen += truth, imageSeen += byImage;
    hiddenButSeen += truth && !byImage, seenButHidden += byImage && !truth;
  }
  return {double(hiddenButSeen) / double(std::max<std::size_t>(seen, 1)),
          double(seenButHidden) / double(std::max<std::size_t>(imageSeen, 1))};
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
  rain::EyeDepth image;      // of the camera (still), when the rain keeps what the eye sees
  rain::RainSpace space;
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
  out.image = r.eyeDepth();
  out.space = r.space();
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

// rain_pour's rain, cup and tray, the cup full of water to 8 cm, the camera aimed at the cup, at
// narrow fields of view and rain_pour's own 40 degrees: the drops are kept where the eye sees
// them (rain.occlusion "depth_map"), so they are uniform in the part of the rain space outside
// the solids and the water that the eye sees, the water taken as its particles' spheres of one
// spacing.
TEST(RainPlacement, AimedAtACupOfWaterNoDropIsParkedAndTheyAreUniformWhereTheEyeSees) {
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
  const test::EyeSight sight(solids, fluid, h);
  for (float fov : {3.0f, 5.0f, 8.0f, 40.0f}) {
    scene::CameraDesc c = *scene.camera;
    c.fovYDegrees = fov;
    scene::RainDesc d = *scene.rain;
    d.count = 100000;
    const Placed p = placeDrops(d, c, obstacles);
    ASSERT_TRUE(p.image.active());
    const Uniformity u =
        imageUniformity(FrustumCube(c, test::kAspect, d.near, d.far), p.drops, p.image);
    const ImageAgainstGeometry g = imageAgainstGeometry(p.space, p.image, sight, obstacles);
    std::size_t blocked = 0, hidden = 0;
    for (const Vec3& q : p.drops) {
      blocked += rain::insideSolid(q, solids) || water.contains(q);
      hidden += !sight.visible(c.position, q);
    }
    std::printf(
        "cup, fov %g: at most %.4f of the budget parked; %zu drops placed, %zu in a solid or the "
        "water, %zu hidden; chi2 depth %.1f (limit %.1f), direction %.1f (limit %.1f); the image "
        "hides %.4f of what the geometry sees, sees %.4f of what it hides\n",
        fov, double(p.mostParked) / double(p.count), p.drops.size(), blocked, hidden, u.chiDepth,
        u.limitDepth, u.chiDirection, u.limitDirection, g.hiddenButSeen, g.seenButHidden);
    EXPECT_EQ(p.mostParked, 0u) << "fov " << fov;
    EXPECT_EQ(p.parked, 0u) << "fov " << fov;
    EXPECT_EQ(blocked, 0u) << "fov " << fov;
    EXPECT_LT(static_cast<double>(hidden), 0.05 * static_cast<double>(p.drops.size()));
    EXPECT_LT(g.seenButHidden, 0.05) << "fov " << fov;
    EXPECT_LT(u.chiDepth, u.limitDepth) << "fov " << fov;
    EXPECT_LT(u.chiDirection, u.limitDirection) << "fov " << fov;
  }
}

}  // namespace
}  // namespace sph
