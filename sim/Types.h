// Small value types shared by the whole simulator. SI units everywhere (metres, seconds, kg).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>

namespace sph {

using Vec3 = Eigen::Vector3f;
using Vec3d = Eigen::Vector3d;

// Axis-aligned box [lo, hi] in metres.
struct Aabb {
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::max());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<float>::max());

  bool empty() const { return (lo.array() > hi.array()).any(); }
  void grow(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void grow(const Aabb& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  bool contains(const Vec3& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
  Vec3 size() const { return hi - lo; }
};

}  // namespace sph
