// The cone spotlight of seed 002 section 3.2, eq. (10)-(13), as DESIGN.md reads it: eq. (12)'s
// "pos_particle - h_spotlight" is the particle relative to the light's position, and "above the
// light" is a point behind the apex along D (updown < 0) or past the cone's height. The GLSL twin
// is shaders/rain_spotlight.glsl; tests/test_rain.cpp checks this one against an angle test.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/scene/RainDesc.h"

namespace sph::rain {

// How much of the light reaches p, in [0, 1]: 1 inside the cone and 0 outside (the paper); with
// softEdge > 0 it falls linearly to 0 over the outer softEdge fraction of the cone's radius, and
// with falloff it is also scaled by 1 / (1 + (updown / height)^2).
inline float spotlightWeight(const scene::SpotlightDesc& l, const Vec3& p) {
  const Vec3 ps = p - l.position;                        // eq. (10)
  const float updown = ps.dot(l.direction);              // eq. (10)
  if (updown < 0 || updown > l.height) return 0;         // above the light (3.2.1) or past the cone
  const float rCone = updown / l.height * l.baseRadius;  // eq. (11)
  const float distOrtho = (ps - updown * l.direction).norm();  // eq. (12), as read
  float w;
  if (l.softEdge <= 0) {
    w = rCone >= distOrtho ? 1.0f : 0.0f;  // eq. (13)
  } else {
    const float inner = (1 - l.softEdge) * rCone;
    w = std::clamp((rCone - distOrtho) / std::max(rCone - inner, 1e-30f), 0.0f, 1.0f);
  }
  if (l.falloff) w /= 1 + (updown / l.height) * (updown / l.height);
  return w;
}

}  // namespace sph::rain
