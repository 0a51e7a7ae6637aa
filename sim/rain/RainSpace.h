// The rain space of seed 002 (Im & Sung 2021, section 3.1): the rain camera's frustum between its
// own near and far distances (eq. (1)-(3)), its four side planes (eq. (4)), the sphere centred
// halfway between the near and far plane centres with radius half their distance (eq. (5)), and
// the side-plane test of eq. (8)-(9). The rain space is frustum intersected with sphere; the
// sphere touches the near and far planes, so the four side planes are the whole frustum test.
#pragma once

#include <array>
#include <cmath>

#include "sim/Types.h"
#include "sim/scene/CameraDesc.h"

namespace sph::rain {

// What a candidate point of the pyramid costs against one of the sphere's cube (measured:
// docs/rain.md, "Narrow fields of view": a drop costs the same either way near 35 degrees).
inline constexpr double kPyramidCandidateCost = 4;

struct RainSpace {
  Vec3 eye, forward, right, up;  // camera basis (up perpendicular to forward)
  float near = 0, far = 0;       // m
  // eq. (3), in the paper's names
  Vec3 fbr, fbl, ftr, ftl, nbr, nbl, ntr, ntl;
  // eq. (4): unit normals of the right, left, bottom and top planes, oriented to point into the
  // frustum (the paper leaves the sign to the order of its cross products).
  Vec3 R, L, B, T;
  Vec3 centre;       // eq. (5)
  float radius = 0;  // eq. (5)
  // The frustum's half height and half width per metre of depth (tan of half the fov, times the
  // aspect): a point at depth z is inside the side planes when its offsets along up and right are
  // within z tanUp and z tanRight.
  float tanUp = 0, tanRight = 0;

  // The rain camera: `camera`'s pose and fov, the viewport's aspect (width / height), the rain's
  // own near and far distances.
  static RainSpace build(const scene::CameraDesc& camera, float aspect, float near, float far);

  // eq. (8)-(9): p - nbl against B and L, p - ntr against R and T; all >= 0 inside.
  bool insideSides(const Vec3& p) const {
    return (along(p, ntr, R) >= 0) & (along(p, nbl, L) >= 0) & (along(p, ntr, T) >= 0) &
           (along(p, nbl, B) >= 0);
  }
  bool insideSphere(const Vec3& p) const { return along(p, centre, p - centre) <= radius * radius; }
  // `&`, not `&&`: no branch, so that a loop over many drops can run in SIMD lanes.
  bool contains(const Vec3& p) const { return insideSphere(p) & insideSides(p); }
  // (p - o).n with explicit fused multiply-adds, x last: the compiler may fuse a dot product's
  // products with its sums or not, and a spawn in SIMD lanes must round as one at a time
  // (sim/rain/ViewSampler.h), so the rounding is written out and the same in every file.
  static float along(const Vec3& p, const Vec3& o, const Vec3& n) {
    return std::fma(p.x() - o.x(), n.x(), std::fma(p.y() - o.y(), n.y(), (p.z() - o.z()) * n.z()));
  }
  // The depth (m) the pyramid's candidates are drawn to: far, or less where nothing beyond is
  // seen (limitDraws).
  float drawDepth = 0;
  // Volume (m^3) of the pyramid from the eye to depth `depth` (the frustum extended to the eye):
  // by default to drawDepth.
  double pyramidVolume(float depth) const {
    return 4.0 / 3.0 * double(tanUp) * double(tanRight) * std::pow(double(depth), 3.0);
  }
  double pyramidVolume() const { return pyramidVolume(drawDepth); }
  // Draws candidates no deeper than `depth` (m) where that is less than far: a spawn that keeps
  // only what the eye sees (sim/rain/EyeDepth.h) wastes none beyond the deepest pixel. Points
  // uniform in the shallower pyramid and kept where they are seen are still uniform there. The
  // choice of the pyramid or the cube is made again for it.
  void limitDraws(float depth);
  // Whether points uniform in the rain space are drawn from that pyramid rather than from the
  // sphere's bounding cube (sim/rain/ViewSampler.h): at a narrow field of view the rain space is
  // a needle holding a tiny share of the cube (0.17% at 3 degrees, 16:9) but most of the
  // pyramid. A pyramid candidate costs kPyramidCandidateCost cube candidates, so the pyramid is
  // taken where its volume times that is the smaller.
  bool drawsFromPyramid() const { return fromPyramid; }
  bool fromPyramid = false;  // build() decides, once a camera
  // Volume (m^3) of frustum intersected with sphere, by a fixed quasi-random estimate (0.3%),
  // drawn from the region drawsFromPyramid() names: 2^18 points of the cube saw ~400 of the
  // rain space at 3 degrees.
  double volume() const;
};

}  // namespace sph::rain
