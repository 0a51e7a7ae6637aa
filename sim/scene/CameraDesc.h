// A camera pose and lens (scene key `camera`, and `collision.pose` for the fixed collision
// camera). Plain data; the matrices are built where they are used (sim/cdt/CdtCamera.h).
#pragma once

#include <vector>

#include "sim/Types.h"

namespace sph::scene {

struct CameraDesc {
  Vec3 position = Vec3(0, 0, 1);  // m
  Vec3 target = Vec3::Zero();     // m
  Vec3 up = Vec3::UnitY();
  float fovYDegrees = 45;         // vertical field of view
  float near = 0.01f, far = 100;  // m
};

// One key frame of a camera path (scene key camera.path[]): the pose and lens at `time`
// (simulated seconds). sim/scene/Camera.h interpolates between them (cameraAt).
struct CameraKey {
  double time = 0;                                       // s
  Vec3 position = Vec3(0, 0, 1), target = Vec3::Zero();  // m
  float fovYDegrees = 45;
};
using CameraPath = std::vector<CameraKey>;  // strictly increasing times

}  // namespace sph::scene
