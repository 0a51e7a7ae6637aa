#include "render/solids/DrawOrder.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace sph::render::solids {
namespace {

float toBox(const Vec3& lo, const Vec3& hi, const Vec3& eye) {
  return (eye.cwiseMax(lo).cwiseMin(hi) - eye).norm();
}

}  // namespace

float nearestDistance(const scene::BoundaryShape& s, float thickness, const Vec3& eye) {
  switch (s.kind) {
    case scene::BoundaryShape::Kind::Sphere:
      return std::max(0.0f, (s.centre - eye).norm() - s.radius);
    case scene::BoundaryShape::Kind::Block:
      return toBox(s.lo, s.hi, eye);
    case scene::BoundaryShape::Kind::Cup: {
      // Its box: the outer wall from the underside to the rim.
      const float outer = s.radius + thickness;
      const Vec3 lo = s.centre - Vec3(outer, thickness, outer);
      const Vec3 hi = s.centre + Vec3(outer, s.height, outer);
      return toBox(lo, hi, eye);
    }
    case scene::BoundaryShape::Kind::Tank:
    case scene::BoundaryShape::Kind::Plane:
      return std::numeric_limits<float>::infinity();
  }
  return std::numeric_limits<float>::infinity();
}

void frontToBack(const std::vector<scene::BoundaryShape>& shapes, float thickness, const Vec3& eye,
                 std::vector<std::size_t>& order, std::vector<float>& distance) {
  distance.resize(shapes.size()), order.resize(shapes.size());
  for (std::size_t i = 0; i < shapes.size(); ++i)
    distance[i] = nearestDistance(shapes[i], thickness, eye);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return distance[a] < distance[b]; });
}

std::vector<std::size_t> frontToBack(const std::vector<scene::BoundaryShape>& shapes,
                                     float thickness, const Vec3& eye) {
  std::vector<std::size_t> order;
  std::vector<float> distance;
  frontToBack(shapes, thickness, eye, order, distance);
  return order;
}

}  // namespace sph::render::solids
