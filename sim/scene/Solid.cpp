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

}  // namespace

Solid::Solid(const BoundaryShape& shape, float thickness) : shape_(shape), thickness_(thickness) {
  if (shape_.kind == BoundaryShape::Kind::Plane) shape_.normal.normalize();
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

Aabb Solid::bounds() const {
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

bool keepOutside(const Solid& solid, const Vec3& xOld, Vec3& xNew, Vec3& v, float step) {
  const float dNew = solid.distance(xNew);
  const Vec3 travel = xNew - xOld;
  const float length = travel.norm();
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
  // March along the segment at `step` so a wall thicker than 2 steps cannot be jumped over.
  const int samples = std::max(1, static_cast<int>(std::ceil(length / step)));
  float tOut = 0.0f, tIn = -1.0f;
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
