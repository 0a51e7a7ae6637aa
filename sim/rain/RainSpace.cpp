#include "sim/rain/RainSpace.h"

#include <cmath>

#include "sim/rain/RainRandom.h"
#include "sim/scene/Camera.h"

namespace sph::rain {

RainSpace RainSpace::build(const scene::CameraDesc& camera, float aspect, float near, float far) {
  RainSpace s;
  // V of eq. (2) is the basis's forward, RIGHT = V x UP (normalised) its right.
  const scene::CameraBasis basis = scene::cameraBasis(camera);
  s.eye = basis.eye, s.forward = basis.forward, s.right = basis.right, s.up = basis.up;
  s.near = near, s.far = far;
  // eq. (1)
  const float t = scene::tanHalfFovY(camera);
  s.tanUp = t, s.tanRight = t * aspect;
  const float hFar = 2 * t * far, wFar = hFar * aspect;
  const float hNear = 2 * t * near, wNear = hNear * aspect;
  // eq. (2)
  const Vec3 cFar = s.eye + s.forward * far, cNear = s.eye + s.forward * near;
  // eq. (3)
  const Vec3 uf = s.up * (0.5f * hFar), rf = s.right * (0.5f * wFar);
  const Vec3 un = s.up * (0.5f * hNear), rn = s.right * (0.5f * wNear);
  s.fbr = cFar - uf + rf, s.fbl = cFar - uf - rf, s.ftr = cFar + uf + rf, s.ftl = cFar + uf - rf;
  s.nbr = cNear - un + rn, s.nbl = cNear - un - rn, s.ntr = cNear + un + rn;
  s.ntl = cNear + un - rn;
  // eq. (5)
  s.centre = 0.5f * (cFar + cNear);
  s.radius = 0.5f * (cFar - cNear).norm();
  // eq. (4), each normal turned to face the sphere centre (which is inside the frustum)
  auto inward = [&](Vec3 n, const Vec3& onPlane) {
    n.normalize();
    return n.dot(s.centre - onPlane) >= 0 ? n : Vec3(-n);
  };
  s.R = inward((s.nbr - s.fbr).cross(s.nbr - s.ntr), s.nbr);
  s.L = inward((s.nbl - s.fbl).cross(s.nbl - s.ntl), s.nbl);
  s.B = inward((s.nbl - s.nbr).cross(s.nbl - s.fbl), s.nbl);
  s.T = inward((s.ntl - s.ftl).cross(s.ntl - s.ntr), s.ntl);
  s.drawDepth = far;
  s.fromPyramid = kPyramidCandidateCost * s.pyramidVolume() < 8.0 * std::pow(double(s.radius), 3.0);
  return s;
}

void RainSpace::limitDraws(float depth) {
  if (!(depth < far)) return;
  drawDepth = depth;
  fromPyramid = kPyramidCandidateCost * pyramidVolume() < 8.0 * std::pow(double(radius), 3.0);
}

double RainSpace::volume() const {
  constexpr int kSamples = 1 << 18;
  const double cube = 8.0 * std::pow(static_cast<double>(radius), 3.0);
  const bool pyramid = drawsFromPyramid();
  int inside = 0;
  for (int i = 0; i < kSamples; ++i) {
    const Vec3 q(2 * unitRandom(0x5eed, i, 0, 0) - 1, 2 * unitRandom(0x5eed, i, 0, 1) - 1,
                 2 * unitRandom(0x5eed, i, 0, 2) - 1);
    if (pyramid) {
      // The pyramid's points uniformly: depth far cbrt(u), whose density grows as depth^2 as
      // the cross-section does, and the offsets uniform across it.
      const float z = far * std::cbrt(0.5f * (q.z() + 1));
      const Vec3 p = eye + z * forward + (z * tanRight * q.x()) * right + (z * tanUp * q.y()) * up;
      inside += insideSphere(p) && insideSides(p);
    } else {
      if (q.squaredNorm() > 1) continue;
      if (insideSides(centre + radius * q)) ++inside;
    }
  }
  return (pyramid ? pyramidVolume(far) : cube) * inside / kSamples;
}

}  // namespace sph::rain
