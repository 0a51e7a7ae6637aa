// The frame, camera and rain of bench_rain's benchmarks (docs/benchmarks.md, "View-dependent
// rain"): 960 x 540 pixels, a camera at (0, 1, 4) panning 90 degrees a second at 30 fps, and rain
// near 0.1 m to far 5 m with a 10 x 5 x 10 m region for the `region` spawn.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/rain/RainSystem.h"
#include "sim/scene/Camera.h"
#include "sim/scene/RainDesc.h"
#include "sim/scene/Solid.h"

namespace sph::bench {

inline constexpr int kWidth = 960, kHeight = 540;
inline constexpr float kAspect = static_cast<float>(kWidth) / kHeight;

inline scene::CameraDesc cameraAtFrame(int frame) {
  scene::CameraDesc c;
  c.position = Vec3(0, 1, 4);
  const double a = frame / 30.0 * M_PI / 2;  // 90 degrees a second
  c.target =
      c.position + Vec3(static_cast<float>(-std::sin(a)), 0, static_cast<float>(-std::cos(a)));
  c.fovYDegrees = 45;
  return c;
}

// A tray and a cup under the rain (RainUpdateSolids): a 10 x 10 m open tank 0.3 m deep around
// the camera's feet and a cup 1 m across 2 m ahead, walls and floors 1 cm thick as in
// scenes/rain_pour.json, so that drops falling 0.2 m a frame cross them.
inline std::vector<scene::Solid> solids() {
  scene::BoundaryShape tray, cup;
  tray.kind = scene::BoundaryShape::Kind::Tank;
  tray.lo = Vec3(-5, 0, -5), tray.hi = Vec3(5, 0.3f, 5), tray.openTop = true;
  cup.kind = scene::BoundaryShape::Kind::Cup;
  cup.centre = Vec3(0, 0, 2), cup.radius = 0.5f, cup.height = 0.6f;
  return {scene::Solid(tray, 0.01f), scene::Solid(cup, 0.01f)};
}

inline scene::RainDesc desc(std::int64_t count, std::int64_t spawn) {
  scene::RainDesc d;
  d.count = static_cast<std::size_t>(count);
  d.near = 0.1f, d.far = 5;
  d.spawn = static_cast<scene::RainSpawn>(spawn);
  d.region.lo = Vec3(-5, -1, -5), d.region.hi = Vec3(5, 4, 5);
  return d;
}

// The drops of `r` inside the rain camera's frustum near..far for `camera` (the drops a frame
// draws where nothing is in the way), from the general camera maths (sim/scene/Camera.h), not the
// rain's own test.
inline std::size_t dropsInFrustum(const rain::RainSystem& r, const scene::CameraDesc& camera,
                                  const scene::RainDesc& d) {
  const scene::Frustum frustum = scene::viewFrustum(camera, kAspect, d.near, d.far);
  std::size_t in = 0;
  for (const Vec3& p : r.positions()) {
    bool inside = true;
    for (int k = 0; k < 6; ++k) inside = inside && frustum.distance(k, p) >= 0;
    in += inside;
  }
  return in;
}

}  // namespace sph::bench
