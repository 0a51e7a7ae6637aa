// Lights and solids for the particle-light tests (test_lights, test_lights_volume,
// test_lights_filters, test_lights_cull, test_lights_cpu, test_lights_shade).
#pragma once

#include <algorithm>
#include <cstdlib>
#include <random>
#include <vector>

#include "render/splat/SplatRenderer.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/CameraDesc.h"
#include "sim/scene/Scene.h"

namespace sph::test {

// A light at p of `colour` times `intensity`, its direction weighted by `intensity`.
inline lights::LightParticle light(const Vec3& p, const Vec3& colour, float intensity) {
  return {{p.x(), p.y(), p.z(), 0.0f},
          {colour.x() * intensity, colour.y() * intensity, colour.z() * intensity, intensity}};
}

// A floor at y = 0, a sphere and a block on it: something for the lights to light.
inline std::vector<scene::BoundaryShape> floorSphereBlock(const Vec3& centre, float radius,
                                                          const Vec3& blockLo,
                                                          const Vec3& blockHi) {
  scene::BoundaryShape plane, sphere, block;
  plane.kind = scene::BoundaryShape::Kind::Plane, plane.point = Vec3::Zero(),
  plane.normal = Vec3::UnitY();
  sphere.kind = scene::BoundaryShape::Kind::Sphere, sphere.centre = centre, sphere.radius = radius;
  block.kind = scene::BoundaryShape::Kind::Block, block.lo = blockLo, block.hi = blockHi;
  return {plane, sphere, block};
}

// The scene two renderings of one frame are compared on (forward against deferred, GL against
// CPU shading): 96 warm lights over a floor, a sphere and a block, a sheet of point splats over
// the floor partly behind the sphere, and a camera that sees them all.
inline std::vector<lights::LightParticle> sheetLights(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<lights::LightParticle> lights;
  for (int i = 0; i < 96; ++i)
    lights.push_back(light(Vec3(u(rng) - 0.5f, 0.02f + 0.4f * u(rng), u(rng) - 0.5f),
                           Vec3(1.0f, 0.4f + 0.6f * u(rng), 0.2f + 0.8f * u(rng)), 0.5f));
  return lights;
}
inline std::vector<scene::BoundaryShape> sheetSolids() {
  return floorSphereBlock(Vec3(0, 0.15f, 0), 0.15f, Vec3(0.15f, 0, -0.35f),
                          Vec3(0.35f, 0.2f, -0.15f));
}
inline render::splat::SplatFrame waterSheet() {
  render::splat::SplatFrame water;
  water.halfSize = 0.03f;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i)
      water.points.push_back(
          render::splat::SplatVertex{{-0.45f + 0.06f * i, 0.04f, -0.45f + 0.06f * j}, {0, 1, 0}});
  return water;
}
inline scene::CameraDesc sheetCamera() {
  scene::CameraDesc camera;
  camera.position = Vec3(0.6f, 0.55f, 0.8f), camera.target = Vec3(0, 0.1f, 0);
  camera.fovYDegrees = 50;
  return camera;
}

// Two pictures of one frame: the largest difference of a channel (8-bit steps), and how many
// channels of `a` differ from `unlit` by more than 8 steps (that the lights show at all).
struct Steps {
  int worst = 0, lit = 0;
};
inline Steps steps(const render::frame::RenderImage& a, const render::frame::RenderImage& b,
                   const render::frame::RenderImage& unlit) {
  Steps s;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    s.worst = std::max(s.worst, std::abs(int(a.rgb[i]) - int(b.rgb[i])));
    s.lit += std::abs(int(a.rgb[i]) - int(unlit.rgb[i])) > 8;
  }
  return s;
}

}  // namespace sph::test
