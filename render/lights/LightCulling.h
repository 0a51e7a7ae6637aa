// Frustum culling of the particle-light volume (lights.cull; seed 004 section 7's future work;
// docs/lights.md, "Frustum culling"): a frame drawn through one camera samples the volume only at
// points it sees, so only the voxels those points read need to be cleared, accumulated and
// resolved, and only the lights that reach one of those voxels need to run. Plain CPU geometry:
// render/lights/LightVolume.cpp applies it.
//
// Why the image does not change: a visible point p lies inside the frustum grown by `margin`
// (the splats' vertices may lie a little outside it). The filter reads voxels whose centres are
// within filterReach() of p. A light changes such a voxel only if it is within `range` of its
// centre, so a light farther than range + reach + margin outside any frustum plane changes no
// voxel a visible point reads, and with the atomic (integer, order-free) sums every voxel that is
// read holds the same bits as without culling.
#pragma once

#include <array>
#include <vector>

#include "sim/scene/Camera.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/LightsDesc.h"

namespace sph::render::lights {

// The camera a frame is drawn through, as the volume needs it.
struct LightView {
  scene::Mat4 projView;  // the frame's projection * view (sim/scene/Camera.h, cameraFrame)
  float margin = 0;  // m: how far outside the frustum a point may still be shaded (splat vertices)
};
// The view of `camera` over a width / height `aspect` picture, with the margin of the water's
// splats: a splat is built for a particle up to halfSize + R outside the frustum
// (render/splat/SplatBuilder.cpp), and its vertices lie up to halfSize (corner) + max(halfSize,
// R) (the move onto the surface) from the particle: 3 halfSize + 2 R covers both. `splatSize`
// and `kernelRadius` in spacings (RenderDesc), `spacing` in m.
LightView lightView(const scene::CameraDesc& camera, float aspect, float splatSize,
                    float kernelRadius, float spacing);

// How far (m) from a shaded point the voxel centres the filter reads may lie: per axis half a
// voxel (nearest), one (trilinear), two (tricubic's 4x4x4), half a voxel more with oversampling
// (its samples spread over one voxel around the point); times sqrt(3) for the diagonal.
float filterReach(const scene::LightsDesc& desc);

// A box of voxels: lo <= v < hi on each axis (empty when any hi <= lo).
struct VoxelBox {
  std::array<int, 3> lo{}, hi{};
  bool empty() const { return hi[0] <= lo[0] || hi[1] <= lo[1] || hi[2] <= lo[2]; }
  std::size_t count() const;
  bool contains(const std::array<int, 3>& v) const;
};
VoxelBox wholeVolume(const scene::LightsDesc& desc);
// The smallest box holding every voxel a point seen through `view` may read: the volume clipped
// by the frustum grown by margin + filterReach (the vertices of that convex solid, each the
// meeting of three of its twelve planes), widened by one voxel for rounding.
VoxelBox viewVoxels(const scene::LightsDesc& desc, const LightView& view);

// Whether a light may change a voxel of `box` read from `view`: within range + filterReach +
// margin of the frustum (each plane) and within range of the box's voxel centres. Made once a
// frame; the CPU accumulation asks it while it bins the lights, with no copy of the kept ones.
class ViewCull {
 public:
  ViewCull(const scene::LightsDesc& desc, const LightView& view, const VoxelBox& box);
  bool keeps(const sph::lights::LightParticle& light) const {
    const Vec3 p(light.position[0], light.position[1], light.position[2]);
    if (empty_ || !frustum_.sphereVisible(p, reach_)) return false;
    return (p.cwiseMax(lo_).cwiseMin(hi_) - p).squaredNorm() <= range_ * range_;
  }
  // What keeps() tests, for a vectorised copy of it (CpuAccumulation.cpp: 16 lights at a time).
  const scene::Frustum& frustum() const { return frustum_; }
  float reach() const { return reach_; }
  float range() const { return range_; }
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }
  bool empty() const { return empty_; }

 private:
  scene::Frustum frustum_;
  float reach_ = 0, range_ = 0;
  Vec3 lo_, hi_;  // the box's outermost voxel centres
  bool empty_ = true;
};

// The lights of `lights` that ViewCull(desc, view, box) keeps, in their order.
std::vector<sph::lights::LightParticle> lightsInView(
    const scene::LightsDesc& desc, const std::vector<sph::lights::LightParticle>& lights,
    const LightView& view, const VoxelBox& box);

}  // namespace sph::render::lights
