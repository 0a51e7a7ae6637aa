// General camera maths, one home for every part that looks through a camera: the CDT's collision
// camera (sim/cdt/CdtCamera.h), the splat renderer (render/splat/), the reference ray-marcher and
// the view-dependent parts to come. Conventions of OpenGL / GLU: the camera looks down its -z
// axis, matrices are column-major like GLSL's mat4, NDC z in [-1, 1].
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "sim/scene/CameraDesc.h"

namespace sph::scene {

// 4x4 float matrix, column-major like GLSL's mat4 and glUniformMatrix4fv(..., GL_FALSE, ...):
// row r, column c is m[4 c + r].
struct Mat4 {
  std::array<float, 16> m{};
  float operator()(int row, int column) const {
    return m[static_cast<std::size_t>(4 * column + row)];
  }
};

Mat4 identity();
// a * b, each entry summed in double and rounded once.
Mat4 multiply(const Mat4& a, const Mat4& b);
// gluLookAt / gluPerspective conventions.
Mat4 lookAt(const Vec3& eye, const Vec3& target, const Vec3& up);
Mat4 perspective(float fovYDegrees, float aspect, float near, float far);

// The orthonormal basis of a camera, as gluLookAt builds it: `forward` along the view direction,
// `right` = forward x the desc's up hint, `up` perpendicular to both (not the hint).
struct CameraBasis {
  Vec3 eye, forward, right, up;
};
// Inline, so that it rounds as the file that calls it is built: Camera.cpp without FMA
// contraction (cameraFrame's matrices feed the CDT's texel addressing), the rain space and the
// reference ray-marcher with their own files' flags (their drops and pixels are pinned with them).
inline CameraBasis cameraBasis(const CameraDesc& camera) {
  CameraBasis b;
  b.eye = camera.position;
  b.forward = (camera.target - camera.position).normalized();
  b.right = b.forward.cross(camera.up).normalized();
  b.up = b.right.cross(b.forward);
  return b;
}
// tan of half the vertical field of view: a point at distance z along `forward` is in the picture
// where its offset along `up` is within z tanHalfFovY, along `right` within aspect times that.
inline float tanHalfFovY(const CameraDesc& camera) {
  return std::tan(0.5f * camera.fovYDegrees * static_cast<float>(M_PI) / 180.0f);
}

// The matrices and orthonormal basis of a camera for a viewport aspect ratio (width / height).
struct CameraFrame : CameraBasis {
  Mat4 projView;
};
CameraFrame cameraFrame(const CameraDesc& camera, float aspect);

// The camera at time t (s) along a key-frame path (scene key camera.path): `base` (its up, near,
// far, and the pose when the path is empty) with the pose and fov of the path. Before the first
// key the first holds, after the last the last. Between keys: the eye moves linearly, the view
// direction turns at a constant rate about the axis between the two (slerp) while the distance
// to the target and the fov change linearly, so a two-key pan turns evenly.
CameraDesc cameraAt(const CameraDesc& base, const CameraPath& path, double t);

// The six planes of the frustum of a projection * view matrix (Gribb & Hartmann 2001): a point p
// is inside when a.p + d >= 0 for all of them, with (a, d) normalised so that value is a distance
// in metres. Order: left, right, bottom, top, near, far.
struct Frustum {
  std::array<Eigen::Vector4f, 6> planes;
  explicit Frustum(const Mat4& projView);
  // Signed distance (m) of p from plane k, positive inside.
  float distance(int k, const Vec3& p) const { return planes[k].head<3>().dot(p) + planes[k].w(); }
  bool sphereVisible(const Vec3& centre, float radius) const {
    for (int k = 0; k < 6; ++k) {
      if (distance(k, centre) < -radius) return false;
    }
    return true;
  }
};

// The frustum of `camera` over a viewport of `aspect`, cut at distances near and far instead of
// the camera's own (the rain's: its near and far).
Frustum viewFrustum(const CameraDesc& camera, float aspect, float near, float far);

}  // namespace sph::scene
