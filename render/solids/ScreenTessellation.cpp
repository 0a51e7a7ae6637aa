#include "render/solids/ScreenTessellation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/solver/Kernels.h"

namespace sph::render::solids {

int segmentsFor(float radiusPixels, const TessellationBound& b) {
  const int floor = std::max(4, (b.floor + 3) / 4 * 4), cap = std::max(floor, b.cap / 4 * 4);
  if (!(radiusPixels > 0)) return floor;
  if (!std::isfinite(radiusPixels) || b.pixels <= 0) return cap;
  // r sin^2(pi / n) <= pixels  <=>  pi / n <= asin(sqrt(pixels / r)).
  const double s = std::sqrt(std::min(1.0, static_cast<double>(b.pixels) / radiusPixels));
  const double n = solver::kPi / std::asin(s);
  const int wanted = static_cast<int>(std::ceil(n / 4 - 1e-9)) * 4;
  return std::clamp(wanted, floor, cap);
}

float radiusOnScreen(const scene::Mat4& pv, int width, int height, const Vec3& centre,
                     float boundRadius, float radius) {
  if (!scene::Frustum(pv).sphereVisible(centre, boundRadius)) return 0.0f;
  auto rowDot = [&](int r) {
    return pv(r, 0) * centre.x() + pv(r, 1) * centre.y() + pv(r, 2) * centre.z() + pv(r, 3);
  };
  auto rowLength = [&](int r) { return Vec3(pv(r, 0), pv(r, 1), pv(r, 2)).norm(); };
  // Clip w is the depth along the view axis (perspective()'s row 3 is -z of the view, a unit
  // row under a rigid view). Rows 0 and 1 are the view's x and y times the projection's scales
  // (f / aspect, f): pixels per metre at depth w are those scales times half the viewport / w.
  const float w = rowDot(3), depthScale = rowLength(3);
  const float nearest = w - boundRadius * depthScale;
  if (nearest <= 1e-6f * std::max(1.0f, std::abs(w))) return std::numeric_limits<float>::infinity();
  const float sx = rowLength(0), sy = rowLength(1);
  const float pixelsPerMetre = std::max(0.5f * width * sx, 0.5f * height * sy) / nearest;
  // 1 / cos of the centre's angle off the view axis: sqrt(1 + tan^2), tan from its clip x, y.
  const float tx = rowDot(0) / (w * sx), ty = rowDot(1) / (w * sy);
  return radius * pixelsPerMetre * std::sqrt(1.0f + tx * tx + ty * ty);
}

int screenSegments(const scene::BoundaryShape& s, float thickness, const scene::Mat4& pv, int width,
                   int height, const TessellationBound& bound) {
  switch (s.kind) {
    case scene::BoundaryShape::Kind::Sphere:
      return segmentsFor(radiusOnScreen(pv, width, height, s.centre, s.radius, s.radius), bound);
    case scene::BoundaryShape::Kind::Cup: {
      // From the underside (thickness below the floor) to the rim; the outer wall's radius.
      const float outer = s.radius + thickness, half = 0.5f * (s.height + thickness);
      const Vec3 middle = s.centre + Vec3(0, half - thickness, 0);
      const float bound3 = std::sqrt(outer * outer + half * half);
      return segmentsFor(radiusOnScreen(pv, width, height, middle, bound3, outer), bound);
    }
    case scene::BoundaryShape::Kind::Tank:
    case scene::BoundaryShape::Kind::Block:
    case scene::BoundaryShape::Kind::Plane:
      return 0;
  }
  return 0;
}

}  // namespace sph::render::solids
