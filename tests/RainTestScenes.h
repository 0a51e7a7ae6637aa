// The camera, rain and frustum test the CPU rain suites share (test_rain, test_rain_space,
// test_rain_scene): a 16:9 camera looking along -z, rain of a given spawn model near 0.1 m to far
// 5 m, and the share of the drops inside the view frustum.
#pragma once

#include <cstddef>

#include "sim/scene/Camera.h"
#include "sim/rain/RainSystem.h"

namespace sph::test {

inline constexpr float kAspect = 16.0f / 9.0f;

inline scene::CameraDesc lookingAlongZ() {
  scene::CameraDesc c;
  c.position = Vec3(0, 1, 4);
  c.target = Vec3(0, 1, 0);
  c.fovYDegrees = 45;
  return c;
}

inline scene::RainDesc rainDesc(scene::RainSpawn spawn, std::size_t count = 20000) {
  scene::RainDesc d;
  d.count = count;
  d.near = 0.1f;
  d.far = 5;
  d.spawn = spawn;
  d.region.lo = Vec3(-3, -1, -3), d.region.hi = Vec3(3, 4, 3);
  return d;
}

inline bool inFrustum(const scene::Frustum& f, const Vec3& p) {
  for (int k = 0; k < 6; ++k) {
    if (f.distance(k, p) < -1e-4f) return false;
  }
  return true;
}

inline double fractionInView(const rain::RainSystem& r, const scene::CameraDesc& camera) {
  // The rain camera's frustum from the general camera maths (sim/scene/Camera.h), not RainSpace.
  const scene::Frustum f = scene::viewFrustum(camera, kAspect, r.desc().near, r.desc().far);
  std::size_t in = 0;
  for (const Vec3& p : r.positions()) in += inFrustum(f, p);
  return static_cast<double>(in) / static_cast<double>(r.size());
}

}  // namespace sph::test
