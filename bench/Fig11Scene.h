// The world of seed 004's Fig. 11 as bench_lights and bench_lights_faster draw it
// (docs/benchmarks.md, "Particle lights"): 1 m voxels over 128^3 m, range 0.5 m and attenuation
// [1, 0, 1] as Table 1, with something to light - a floor, 36 spheres of 6 m and 16 blocks
// standing in for its bunny and dragon, overlapping on screen - under lights in the lowest 24 m.
#pragma once

#include <vector>

#include "sim/scene/CameraDesc.h"
#include "sim/scene/LightsDesc.h"
#include "sim/scene/Scene.h"

namespace sph::bench {

inline std::vector<scene::BoundaryShape> fig11Solids() {
  std::vector<scene::BoundaryShape> shapes;
  scene::BoundaryShape floor;
  floor.kind = scene::BoundaryShape::Kind::Plane, floor.point = Vec3::Zero(),
  floor.normal = Vec3::UnitY();
  shapes.push_back(floor);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      scene::BoundaryShape s;
      s.kind = scene::BoundaryShape::Kind::Sphere;
      s.centre = Vec3(14.0f + 20.0f * i, 6.0f, 14.0f + 20.0f * j), s.radius = 6.0f;
      shapes.push_back(s);
    }
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      scene::BoundaryShape b;
      b.kind = scene::BoundaryShape::Kind::Block;
      b.lo = Vec3(20.0f + 28.0f * i, 0, 22.0f + 28.0f * j), b.hi = b.lo + Vec3(8, 14, 8);
      shapes.push_back(b);
    }
  return shapes;
}

// The camera of Fig. 11's table: the whole floor in view.
inline scene::CameraDesc fig11Camera() {
  scene::CameraDesc camera;
  camera.position = Vec3(64, 45, 150), camera.target = Vec3(64, 0, 50), camera.fovYDegrees = 60;
  camera.near = 1, camera.far = 400;
  return camera;
}

// `n` emitter lights in the lowest 24 m, 1 m voxels over 128^3, trilinear, atomic.
inline scene::LightsDesc fig11Lights(std::size_t n) {
  scene::LightsDesc d;
  d.origin = Vec3::Zero(), d.voxelSize = 1.0f, d.voxels = {128, 128, 128};
  d.range = 0.5f, d.attenuation = {1.0f, 0.0f, 1.0f};
  d.source = scene::LightSource::Emitter;
  d.emitter.box.lo = Vec3::Zero(), d.emitter.box.hi = Vec3(128, 24, 128);
  d.emitter.count = n, d.emitter.seed = 11, d.emitter.speed = 0;
  d.colour = Vec3(1.0f, 0.8f, 0.4f), d.roomLight = 0.2f;
  return d;
}

}  // namespace sph::bench
