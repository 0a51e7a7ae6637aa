// Lights and solids for the particle-light tests (test_lights, test_lights_cull, test_lights_cpu).
#pragma once

#include <vector>

#include "sim/LightParticles.h"
#include "sim/Scene.h"

namespace sph::test {

// A light at p of `colour` times `intensity`, its direction weighted by `intensity`.
inline LightParticle light(const Vec3& p, const Vec3& colour, float intensity) {
  return {{p.x(), p.y(), p.z(), 0.0f},
          {colour.x() * intensity, colour.y() * intensity, colour.z() * intensity, intensity}};
}

// A floor at y = 0, a sphere and a block on it: something for the lights to light.
inline std::vector<BoundaryShape> floorSphereBlock(const Vec3& centre, float radius,
                                                   const Vec3& blockLo, const Vec3& blockHi) {
  BoundaryShape plane, sphere, block;
  plane.kind = BoundaryShape::Kind::Plane, plane.point = Vec3::Zero(), plane.normal = Vec3::UnitY();
  sphere.kind = BoundaryShape::Kind::Sphere, sphere.centre = centre, sphere.radius = radius;
  block.kind = BoundaryShape::Kind::Block, block.lo = blockLo, block.hi = blockHi;
  return {plane, sphere, block};
}

}  // namespace sph::test
