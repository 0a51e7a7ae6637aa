// What the CPU streak raster (render/rain/StreakRaster.h) shares between its files: the
// window-homogeneous map of a frame and small helpers. Internal to render/rain.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/Types.h"

namespace sph::render::rain::detail {

struct Vec4f {
  float x, y, z, w;
  Vec4f operator+(const Vec4f& o) const { return {x + o.x, y + o.y, z + o.z, w + o.w}; }
  Vec4f operator-(const Vec4f& o) const { return {x - o.x, y - o.y, z - o.z, w - o.w}; }
  Vec4f operator*(float s) const { return {x * s, y * s, z * s, w * s}; }
};

// What is the same for every streak of a frame. Points are carried in "window-homogeneous"
// coordinates (X', Y', Z', W) = ((X + W) w / 2, (Y + W) h / 2, (Z + W) / 2, W) of the clip
// coordinates (X, Y, Z, W): X' / W is the window x in pixels and Z' / W the window depth, and the
// map stays linear, so a streak is a parallelogram there as in the world.
struct Frame {
  float m[4][4];         // world -> window-homogeneous, m[row][column]
  Vec4f along;           // the streak's tail-to-head vector (exposure x velocity), transformed
  Vec3 dir, eye, right;  // m; the tail-to-head vector in the world
  float halfWidth;       // m
  // At most how far a corner is from its end of the streak in X', Y' and W: the half-width
  // times the norm of the matrix row.
  float marginX, marginY, marginW;
  int width, height;  // pixels
  Vec4f apply(const Vec3& p, float w) const {
    return {m[0][0] * p.x() + m[0][1] * p.y() + m[0][2] * p.z() + m[0][3] * w,
            m[1][0] * p.x() + m[1][1] * p.y() + m[1][2] * p.z() + m[1][3] * w,
            m[2][0] * p.x() + m[2][1] * p.y() + m[2][2] * p.z() + m[2][3] * w,
            m[3][0] * p.x() + m[3][1] * p.y() + m[3][2] * p.z() + m[3][3] * w};
  }
};

inline int floorToInt(float v, int lo, int hi) {
  return static_cast<int>(
      std::floor(std::clamp(v, static_cast<float>(lo), static_cast<float>(hi))));
}

// Row r of the world -> window-homogeneous map applied to the point (x, y, z): Frame::apply's
// arithmetic on plain floats, for the loops over drops in SIMD lanes.
inline float applyRow(const float (&r)[4], float x, float y, float z) {
  return r[0] * x + r[1] * y + r[2] * z + r[3];
}

}  // namespace sph::render::rain::detail
