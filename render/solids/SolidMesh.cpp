#include "render/solids/SolidMesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/solver/Kernels.h"
#include "sim/scene/Solid.h"

namespace sph::render::solids {
namespace {

std::uint32_t vertex(SolidMesh& m, const Vec3& p, const Vec3& n) {
  SolidVertex v;
  for (int a = 0; a < 3; ++a) v.position[a] = p[a], v.normal[a] = n[a];
  m.vertices.push_back(v);
  return static_cast<std::uint32_t>(m.vertices.size() - 1);
}

// A flat convex quad with corners a-b-c-d in order around it, facing `n` (wound
// counter-clockwise seen from that side, whichever way round the corners were given).
void quad(SolidMesh& m, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& n) {
  const std::uint32_t i = vertex(m, a, n), j = vertex(m, b, n), k = vertex(m, c, n),
                      l = vertex(m, d, n);
  if ((b - a).cross(c - a).dot(n) >= 0)
    m.indices.insert(m.indices.end(), {i, j, k, i, k, l});
  else
    m.indices.insert(m.indices.end(), {i, k, j, i, l, k});
}

// The face of the box [lo, hi] on axis `axis` at its `high` side, facing `outward` (true: away
// from the box's inside, as a block's; false: into it, as a tank's inner walls).
void boxFace(SolidMesh& m, const Vec3& lo, const Vec3& hi, int axis, bool high, bool outward) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  Vec3 n = Vec3::Zero();
  n[axis] = (high == outward) ? 1.0f : -1.0f;
  auto corner = [&](float su, float sv) {
    Vec3 p;
    p[axis] = high ? hi[axis] : lo[axis];
    p[u] = su > 0 ? hi[u] : lo[u];
    p[v] = sv > 0 ? hi[v] : lo[v];
    return p;
  };
  // (u, v, n) is right-handed when n points along +axis: counter-clockwise seen from +axis.
  if (n[axis] > 0)
    quad(m, corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1), n);
  else
    quad(m, corner(0, 0), corner(0, 1), corner(1, 1), corner(1, 0), n);
}

// A ring band between heights y0 < y1 at radius r around the vertical axis through c, facing
// away from the axis (outward) or towards it.
void cylinder(SolidMesh& m, const Vec3& c, float r, float y0, float y1, int segments,
              bool outward) {
  const std::uint32_t first = static_cast<std::uint32_t>(m.vertices.size());
  for (int s = 0; s <= segments; ++s) {
    const float phi = static_cast<float>(2 * solver::kPi) * s / segments;
    const Vec3 radial(std::cos(phi), 0, std::sin(phi));
    const Vec3 n = outward ? radial : -radial;
    vertex(m, Vec3(c.x() + r * radial.x(), y0, c.z() + r * radial.z()), n);
    vertex(m, Vec3(c.x() + r * radial.x(), y1, c.z() + r * radial.z()), n);
  }
  for (int s = 0; s < segments; ++s) {
    const std::uint32_t a = first + 2 * s, b = a + 1, cc = a + 2, d = a + 3;
    // Increasing phi turns from +x towards +z, which is clockwise seen from above (+y).
    if (outward)
      m.indices.insert(m.indices.end(), {a, b, d, a, d, cc});
    else
      m.indices.insert(m.indices.end(), {a, d, b, a, cc, d});
  }
}

// An annulus (inner radius r0 >= 0, outer r1) at height y, facing up or down.
void annulus(SolidMesh& m, const Vec3& c, float r0, float r1, float y, int segments, bool up) {
  const Vec3 n = up ? Vec3(0, 1, 0) : Vec3(0, -1, 0);
  const std::uint32_t first = static_cast<std::uint32_t>(m.vertices.size());
  for (int s = 0; s <= segments; ++s) {
    const float phi = static_cast<float>(2 * solver::kPi) * s / segments;
    const float cx = std::cos(phi), cz = std::sin(phi);
    vertex(m, Vec3(c.x() + r0 * cx, y, c.z() + r0 * cz), n);
    vertex(m, Vec3(c.x() + r1 * cx, y, c.z() + r1 * cz), n);
  }
  for (int s = 0; s < segments; ++s) {
    const std::uint32_t a = first + 2 * s, b = a + 1, cc = a + 2, d = a + 3;
    // A full disc (r0 = 0) is a fan: its inner triangle would have no area.
    if (r0 > 0) {
      if (up)
        m.indices.insert(m.indices.end(), {a, cc, d});
      else
        m.indices.insert(m.indices.end(), {a, d, cc});
    }
    if (up)
      m.indices.insert(m.indices.end(), {a, d, b});
    else
      m.indices.insert(m.indices.end(), {a, b, d});
  }
}

void sphere(SolidMesh& m, const Vec3& c, float r, int segments) {
  const int rings = std::max(4, segments / 2);
  const std::uint32_t first = static_cast<std::uint32_t>(m.vertices.size());
  for (int j = 0; j <= rings; ++j) {
    const float theta = static_cast<float>(solver::kPi) * j / rings;  // from the top
    for (int s = 0; s <= segments; ++s) {
      const float phi = static_cast<float>(2 * solver::kPi) * s / segments;
      const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      vertex(m, c + r * n, n);
    }
  }
  const int row = segments + 1;
  for (int j = 0; j < rings; ++j) {
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t a = first + j * row + s, b = a + 1, cc = a + row, d = cc + 1;
      // The rows at the poles are fans (a = b at the top, cc = d at the bottom).
      if (j > 0) m.indices.insert(m.indices.end(), {a, b, d});
      if (j < rings - 1) m.indices.insert(m.indices.end(), {a, d, cc});
    }
  }
}

void plane(SolidMesh& m, const scene::BoundaryShape& s, const Aabb& domain) {
  const scene::PlanePatch p = planeOverDomain(s, domain);
  auto at = [&](float u, float w) { return p.at(u, w, s.point); };
  // t1 then t2 is counter-clockwise seen from n: the quad faces out of the solid.
  quad(m, at(p.lo1, p.lo2), at(p.hi1, p.lo2), at(p.hi1, p.hi2), at(p.lo1, p.hi2), p.n);
}

}  // namespace

void SolidMesh::append(const SolidMesh& other) {
  const std::uint32_t offset = static_cast<std::uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (std::uint32_t i : other.indices) indices.push_back(offset + i);
}

SolidMesh tessellate(const scene::BoundaryShape& s, const Aabb& domain, float thickness,
                     int segments) {
  SolidMesh m;
  switch (s.kind) {
    case scene::BoundaryShape::Kind::Block:
      for (int axis = 0; axis < 3; ++axis)
        for (bool high : {false, true}) boxFace(m, s.lo, s.hi, axis, high, true);
      break;
    case scene::BoundaryShape::Kind::Tank: {
      // A cut-away: the inner walls and floor (and the lid of a closed tank) facing the fluid,
      // and the rim, but not the shell's outside, so from outside one sees in through the near
      // walls (turned away, culled) to the water, the far walls and the floor.
      for (int axis = 0; axis < 3; ++axis) {
        for (bool high : {false, true}) {
          if (axis == 1 && high && s.openTop) continue;
          boxFace(m, s.lo, s.hi, axis, high, false);
        }
      }
      if (s.openTop) {  // the rim: four trapezoids from the inner to the outer top edge
        const Vec3 lo = s.lo - Vec3::Constant(thickness), hi = s.hi + Vec3::Constant(thickness);
        const float y = s.hi.y();
        const Vec3 inner[4] = {Vec3(s.lo.x(), y, s.lo.z()), Vec3(s.hi.x(), y, s.lo.z()),
                               Vec3(s.hi.x(), y, s.hi.z()), Vec3(s.lo.x(), y, s.hi.z())};
        const Vec3 outer[4] = {Vec3(lo.x(), y, lo.z()), Vec3(hi.x(), y, lo.z()),
                               Vec3(hi.x(), y, hi.z()), Vec3(lo.x(), y, hi.z())};
        for (int k = 0; k < 4; ++k)
          quad(m, inner[k], outer[k], outer[(k + 1) % 4], inner[(k + 1) % 4], Vec3::UnitY());
      }
      break;
    }
    case scene::BoundaryShape::Kind::Cup: {
      const Vec3& c = s.centre;
      const float top = c.y() + s.height, bottom = c.y() - thickness;
      cylinder(m, c, s.radius, c.y(), top, segments, false);               // inside wall
      cylinder(m, c, s.radius + thickness, bottom, top, segments, true);   // outside wall
      annulus(m, c, s.radius, s.radius + thickness, top, segments, true);  // rim
      annulus(m, c, 0, s.radius, c.y(), segments, true);                   // inner floor
      annulus(m, c, 0, s.radius + thickness, bottom, segments, false);     // underside
      break;
    }
    case scene::BoundaryShape::Kind::Sphere:
      sphere(m, s.centre, s.radius, segments);
      break;
    case scene::BoundaryShape::Kind::Plane:
      plane(m, s, domain);
      break;
  }
  return m;
}

}  // namespace sph::render::solids
