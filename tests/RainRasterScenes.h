// The frame, camera and rain the streak suites test_rain_raster and test_rain_raster_gl draw:
// 192 x 108 pixels, a camera above and to the right of the rain, and view-model rain slanted by a
// wind and lit in part by a soft-edged spotlight.
#pragma once

#include <cstddef>

#include "sim/scene/Camera.h"
#include "sim/scene/RainDesc.h"

namespace sph::test::streaks {

inline constexpr int kWidth = 192, kHeight = 108;
inline constexpr float kAspect = static_cast<float>(kWidth) / kHeight;

// Above and to the right of the rain, looking down on it a little: no axis of the picture is an
// axis of the world.
inline scene::CameraDesc camera() {
  scene::CameraDesc c;
  c.position = Vec3(0.6f, 1.6f, 4), c.target = Vec3(0, 1, 0);
  c.fovYDegrees = 50;
  return c;
}

// Rain of the view model in front of camera(), slanted by a wind, lit in part by a soft-edged
// spotlight so that the drops' colours differ.
inline scene::RainDesc desc(std::size_t count, scene::RainDraw draw) {
  scene::RainDesc d;
  d.count = count;
  d.near = 0.5f, d.far = 4;
  d.dropWidth = 0.01f;
  d.exposure = 0.03f;
  d.wind = Vec3(2, 0, 0);
  d.seed = 7;
  d.draw = draw;
  d.lodWidth = 0;  // every streak exact, the triangles' picture; the level of detail's tests set it
  scene::SpotlightDesc l;
  l.position = Vec3(-0.8f, 4, 2), l.height = 5, l.baseRadius = 2;
  l.colour = Vec3(1, 0.3f, 0.1f), l.softEdge = 0.3f;
  d.spotlight = l;
  return d;
}

}  // namespace sph::test::streaks
