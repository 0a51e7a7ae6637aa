#include "sim/scene/Solid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sph::scene {
namespace {

constexpr float kOpen = std::numeric_limits<float>::infinity();

// Signed distance to the box [lo, hi]; a face at infinity is open.
float boxDistance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  Vec3 q;
  for (int a = 0; a < 3; ++a) q[a] = std::max(lo[a] - p[a], p[a] - hi[a]);
  const float outside = q.cwiseMax(0.0f).norm();
  const float inside = std::min(q.maxCoeff(), 0.0f);
  return outside + inside;
}

// Signed distance to the y-axis cylinder of radius r around (cx, cz), y in [yLo, yHi].
float cylinderDistance(const Vec3& p, const Vec3& c, float r, float yLo, float yHi) {
  const float dr = std::hypot(p.x() - c.x(), p.z() - c.z()) - r;
  const float dy = std::max(yLo - p.y(), p.y() - yHi);
  const float ox = std::max(dr, 0.0f), oy = std::max(dy, 0.0f);
  return std::sqrt(ox * ox + oy * oy) + std::min(std::max(dr, dy), 0.0f);
}

// The part of a segment a + t d, t in [0, 1], inside a convex piece of a shape: a closed range
// of t, empty when lo > hi.
struct Span {
  float lo = 1, hi = 0;
  bool empty() const { return lo > hi; }
};

Span intersect(const Span& x, const Span& y) {
  return {std::max(x.lo, y.lo), std::min(x.hi, y.hi)};
}

// Along axis k, where lo[k] <= a[k] + t d[k] <= hi[k] (a bound at infinity is open).
Span slabSpan(const Vec3& a, const Vec3& d, const Vec3& lo, const Vec3& hi, int k) {
  if (d[k] == 0) return a[k] >= lo[k] && a[k] <= hi[k] ? Span{0, 1} : Span{};
  float t0 = (lo[k] - a[k]) / d[k], t1 = (hi[k] - a[k]) / d[k];
  if (t0 > t1) std::swap(t0, t1);
  return {std::max(t0, 0.0f), std::min(t1, 1.0f)};
}

// The slab test of the box [lo, hi].
Span boxSpan(const Vec3& a, const Vec3& d, const Vec3& lo, const Vec3& hi) {
  return intersect(intersect(slabSpan(a, d, lo, hi, 0), slabSpan(a, d, lo, hi, 1)),
                   slabSpan(a, d, lo, hi, 2));
}

// Where A t^2 + B t + C <= 0 (A >= 0; a point within a radius), in double: the stable pair of
// roots, so a short segment far from the centre keeps its digits.
Span quadraticSpan(double A, double B, double C) {
  if (A == 0) return C <= 0 ? Span{0, 1} : Span{};  // moving along the axis: B is 0 too
  const double disc = B * B - 4 * A * C;
  if (disc < 0) return {};
  const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
  double t0 = q / A, t1 = q != 0 ? C / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  return {static_cast<float>(std::max(t0, 0.0)), static_cast<float>(std::min(t1, 1.0))};
}

// The y-axis cylinder of radius r around (c.x, c.z), y in [yLo, yHi] (yHi may be infinite).
Span cylinderSpan(const Vec3& a, const Vec3& d, const Vec3& c, float r, float yLo, float yHi) {
  const double ax = a.x() - c.x(), az = a.z() - c.z(), dx = d.x(), dz = d.z();
  const Span round =
      quadraticSpan(dx * dx + dz * dz, 2 * (ax * dx + az * dz), ax * ax + az * az - double(r) * r);
  return intersect(round, slabSpan(a, d, Vec3(0, yLo, 0), Vec3(0, yHi, 0), 1));
}

// The first t in `outer` and not in `hollow` (a container's wall, the outer shape minus its
// hollow), or kNoEntry.
constexpr float kNoEntry = 2;
float firstInWall(const Span& outer, const Span& hollow) {
  if (outer.empty()) return kNoEntry;
  if (hollow.empty() || outer.lo < hollow.lo) return outer.lo;  // reaches the wall from outside
  // Out of the hollow into the wall (the hollow may reach beyond the outer shape: open tops).
  if (outer.hi > hollow.hi) return std::max(outer.lo, hollow.hi);
  return kNoEntry;
}

}  // namespace

Solid::Solid(const BoundaryShape& shape, float thickness) : shape_(shape), thickness_(thickness) {
  if (shape_.kind == BoundaryShape::Kind::Plane) shape_.normal.normalize();
  bounds_ = boundsOf();
}

float Solid::distance(const Vec3& p) const {
  const float t = thickness_;
  switch (shape_.kind) {
    case BoundaryShape::Kind::Tank: {
      // Shell: outer box minus the interior (the interior reaches to infinity if open-topped).
      Vec3 outerLo = shape_.lo - Vec3::Constant(t), outerHi = shape_.hi + Vec3::Constant(t);
      Vec3 innerHi = shape_.hi;
      if (shape_.openTop) outerHi.y() = shape_.hi.y(), innerHi.y() = kOpen;
      return std::max(boxDistance(p, outerLo, outerHi), -boxDistance(p, shape_.lo, innerHi));
    }
    case BoundaryShape::Kind::Block:
      return boxDistance(p, shape_.lo, shape_.hi);
    case BoundaryShape::Kind::Cup: {
      const float floorY = shape_.centre.y(), rimY = floorY + shape_.height;
      const float outer = cylinderDistance(p, shape_.centre, shape_.radius + t, floorY - t, rimY);
      const float inner = cylinderDistance(p, shape_.centre, shape_.radius, floorY, kOpen);
      return std::max(outer, -inner);
    }
    case BoundaryShape::Kind::Plane:
      return (p - shape_.point).dot(shape_.normal);
    case BoundaryShape::Kind::Sphere:
      return (p - shape_.centre).norm() - shape_.radius;
  }
  return kOpen;
}

Vec3 Solid::normal(const Vec3& p, float eps) const {
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    Vec3 d = Vec3::Zero();
    d[a] = eps;
    g[a] = distance(p + d) - distance(p - d);
  }
  const float n = g.norm();
  return n > 0 ? Vec3(g / n) : Vec3::UnitY();
}

Aabb Solid::boundsOf() const {
  Aabb b;
  const float t = thickness_;
  switch (shape_.kind) {
    case BoundaryShape::Kind::Tank:
      b.lo = shape_.lo - Vec3::Constant(t);
      b.hi = shape_.hi + Vec3::Constant(t);
      if (shape_.openTop) b.hi.y() = shape_.hi.y();
      break;
    case BoundaryShape::Kind::Block:
      b.lo = shape_.lo, b.hi = shape_.hi;
      break;
    case BoundaryShape::Kind::Cup: {
      const float r = shape_.radius + t;
      b.lo = shape_.centre + Vec3(-r, -t, -r);
      b.hi = shape_.centre + Vec3(r, shape_.height, r);
      break;
    }
    case BoundaryShape::Kind::Sphere:
      b.lo = shape_.centre - Vec3::Constant(shape_.radius);
      b.hi = shape_.centre + Vec3::Constant(shape_.radius);
      break;
    case BoundaryShape::Kind::Plane:
      break;
  }
  return b;
}

float Solid::segmentEntry(const Vec3& a, const Vec3& b) const {
  // Most segments are nowhere near the solid: their box misses its box.
  if (!bounds_.empty() && ((a.cwiseMax(b).array() < bounds_.lo.array()).any() ||
                           (a.cwiseMin(b).array() > bounds_.hi.array()).any()))
    return kNoEntry;
  const Vec3 d = b - a;
  const float t = thickness_;
  float entry = kNoEntry;
  switch (shape_.kind) {
    case BoundaryShape::Kind::Tank: {  // the shells of distance(), as spans
      Vec3 outerHi = shape_.hi + Vec3::Constant(t), innerHi = shape_.hi;
      if (shape_.openTop) outerHi.y() = shape_.hi.y(), innerHi.y() = kOpen;
      entry = firstInWall(boxSpan(a, d, shape_.lo - Vec3::Constant(t), outerHi),
                          boxSpan(a, d, shape_.lo, innerHi));
      break;
    }
    case BoundaryShape::Kind::Block: {
      const Span s = boxSpan(a, d, shape_.lo, shape_.hi);
      entry = s.empty() ? kNoEntry : s.lo;
      break;
    }
    case BoundaryShape::Kind::Cup: {
      const float floorY = shape_.centre.y(), rimY = floorY + shape_.height;
      entry = firstInWall(cylinderSpan(a, d, shape_.centre, shape_.radius + t, floorY - t, rimY),
                          cylinderSpan(a, d, shape_.centre, shape_.radius, floorY, kOpen));
      break;
    }
    case BoundaryShape::Kind::Plane: {
      const float from = (a - shape_.point).dot(shape_.normal), rate = d.dot(shape_.normal);
      // Inside from the start, or going in and crossing the plane within the segment.
      const float cross = rate < 0 ? -from / rate : kNoEntry;
      entry = from <= 0 ? 0.0f : cross <= 1 ? cross : kNoEntry;
      break;
    }
    case BoundaryShape::Kind::Sphere: {
      const Vec3 o = a - shape_.centre;
      const double r = shape_.radius;
      const Span s = quadraticSpan(double(d.squaredNorm()), 2 * double(o.dot(d)),
                                   double(o.squaredNorm()) - r * r);
      entry = s.empty() ? kNoEntry : s.lo;
      break;
    }
  }
  if (entry <= 1) return entry;
  // The cuts and distance() round differently within a hair of the surface: where they disagree
  // at the end, distance() decides, as it does for every other test of a point.
  if (!bounds_.empty() && !bounds_.contains(b)) return kNoEntry;
  return distance(b) < 0 ? 1.0f : kNoEntry;
}

bool keepOutside(const Solid& solid, const Vec3& xOld, Vec3& xNew, Vec3& v, float step) {
  const Vec3 travel = xNew - xOld;
  const float length = travel.norm();
  // A non-finite move is a blown-up run, which the step's guard reports; marching it would
  // never end.
  if (!std::isfinite(length)) return false;
  const float dNew = solid.distance(xNew);
  // distance() never overestimates the distance, so a particle farther from the solid than it
  // travelled cannot have touched it: the common case costs one distance evaluation.
  if (dNew > length) return false;
  const float eps = 1e-3f * step;
  if (solid.distance(xOld) < 0.0f) {
    // Already inside (placed there, or pushed in by another pass): leave along the normal.
    if (dNew >= 0.0f) return false;
    const Vec3 n = solid.normal(xNew, eps);
    xNew -= (dNew - eps) * n;
    const float vn = v.dot(n);
    if (vn < 0) v -= vn * n;
    return true;
  }
  float tOut = 0.0f;
  if (length > kMarchSteps * step) {
    // Farther in one step than the march is meant for (the step's bound keeps a particle within
    // about a spacing; this one was thrown by a solver blowing up): cut the segment exactly.
    // Marching it took minutes a particle.
    const float entry = solid.segmentEntry(xOld, xNew);
    if (entry > 1.0f) return false;
    tOut = entry;
  } else {
    // March along the segment at `step` so a wall thicker than 2 steps cannot be jumped over.
    const int samples = std::max(1, static_cast<int>(std::ceil(length / step)));
    float tIn = -1.0f;
    for (int k = 1; k <= samples; ++k) {
      const float t = static_cast<float>(k) / samples;
      if (solid.distance(xOld + t * travel) < 0.0f) {
        tIn = t;
        break;
      }
      tOut = t;
    }
    if (tIn < 0.0f) return false;
    for (int it = 0; it < 24; ++it) {  // bisect the entry point to float precision
      const float t = 0.5f * (tOut + tIn);
      (solid.distance(xOld + t * travel) < 0.0f ? tIn : tOut) = t;
    }
  }
  const Vec3 entry = xOld + tOut * travel;
  const Vec3 n = solid.normal(entry, eps);
  xNew = entry + eps * n;
  const float vn = v.dot(n);
  if (vn < 0) v -= vn * n;
  return true;
}

PlanePatch planeOverDomain(const BoundaryShape& s, const Aabb& domain) {
  PlanePatch p;
  p.n = s.normal.normalized();
  const Vec3 helper = std::abs(p.n.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitZ();
  p.t1 = p.n.cross(helper).normalized(), p.t2 = p.n.cross(p.t1);
  p.lo1 = p.lo2 = std::numeric_limits<float>::max(), p.hi1 = p.hi2 = -p.lo1;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c((corner & 1) ? domain.hi.x() : domain.lo.x(),
                 (corner & 2) ? domain.hi.y() : domain.lo.y(),
                 (corner & 4) ? domain.hi.z() : domain.lo.z());
    const float u = (c - s.point).dot(p.t1), w = (c - s.point).dot(p.t2);
    p.lo1 = std::min(p.lo1, u), p.hi1 = std::max(p.hi1, u);
    p.lo2 = std::min(p.lo2, w), p.hi2 = std::max(p.hi2, w);
  }
  return p;
}

}  // namespace sph::scene
