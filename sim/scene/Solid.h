// The geometry of a static boundary shape as a signed distance function (negative inside the
// solid). Boundary particles give the pressure response; the SDF is the safety net that keeps
// any particle from crossing a wall, however fast (DESIGN.md: "no particle may leave through a
// wall"), and tells which initial fluid particles would sit inside a wall.
#pragma once

#include "sim/scene/Scene.h"
#include "sim/Types.h"

namespace sph::scene {

class Solid {
 public:
  // `thickness` (m) is the wall thickness of containers (boundary layers x spacing).
  Solid(const BoundaryShape& shape, float thickness);

  // Signed distance (m) of p to the solid: < 0 inside, > 0 outside. Exact outside for single
  // primitives, a lower bound of the distance for the container shells (max of two SDFs).
  float distance(const Vec3& p) const;
  // Unit outward normal at p (central differences of distance()).
  Vec3 normal(const Vec3& p, float eps) const;
  // Box bounding the solid (planes: unbounded, returns an empty box).
  const Aabb& bounds() const { return bounds_; }
  // The first point of the segment a + t (b - a), t in [0, 1], inside the solid: its t, or a
  // value > 1 when the whole segment is outside. Exact, not sampled: the segment is cut against
  // the shape's boxes, cylinders, sphere or plane, so a wall thinner than the segment is long is
  // not jumped over (a rain drop falls ~10 cm a frame onto a 1 cm floor). Agrees with distance()
  // at the end: when distance(b) < 0 the result is at most 1.
  float segmentEntry(const Vec3& a, const Vec3& b) const;

 private:
  Aabb boundsOf() const;
  BoundaryShape shape_;
  float thickness_;
  Aabb bounds_;  // boundsOf(), once: segmentEntry's first test
};

// Moves a particle that went from xOld to xNew into a solid back to where it entered, and
// removes the velocity component pointing into the solid. Returns true if it acted.
// `step` is the search resolution along the segment (m), at most half the wall thickness. A
// move longer than kMarchSteps steps (a particle thrown by a blow-up) is cut exactly instead.
constexpr float kMarchSteps = 64;
bool keepOutside(const Solid& solid, const Vec3& xOld, Vec3& xNew, Vec3& v, float step);

// The part of an infinite plane shape (BoundaryShape::Kind::Plane) the domain casts onto it: its
// orthonormal frame (t1, t2, n; t2 = n x t1, so t1 then t2 turns counter-clockwise seen from n)
// and the range of the domain's corners along t1 and t2 from s.point. Where its boundary
// particles are sampled and where its solid is drawn.
struct PlanePatch {
  Vec3 t1, t2, n;
  float lo1 = 0, hi1 = 0, lo2 = 0, hi2 = 0;
  Vec3 at(float u, float w, const Vec3& origin) const { return origin + u * t1 + w * t2; }
};
PlanePatch planeOverDomain(const BoundaryShape& plane, const Aabb& domain);

}  // namespace sph::scene
