// A camera pose and lens (scene key `camera`, and `collision.pose` for the fixed collision
// camera). Plain data; the matrices are built where they are used (sim/cdt/CdtCamera.h).
#pragma once

#include "sim/Types.h"

namespace sph {

struct CameraDesc {
  Vec3 position = Vec3(0, 0, 1);  // m
  Vec3 target = Vec3::Zero();     // m
  Vec3 up = Vec3::UnitY();
  float fovYDegrees = 45;         // vertical field of view
  float near = 0.01f, far = 100;  // m
};

}  // namespace sph
