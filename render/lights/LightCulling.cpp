#include "render/lights/LightCulling.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sph::render::lights {

LightView lightView(const scene::CameraDesc& camera, float aspect, float splatSize,
                    float kernelRadius, float spacing) {
  LightView v;
  v.projView = cameraFrame(camera, aspect).projView;
  v.margin = (3 * splatSize + 2 * kernelRadius) * spacing;
  return v;
}

float filterReach(const scene::LightsDesc& d) {
  float perAxis = d.filter == scene::LightFilter::Nearest     ? 0.5f
                  : d.filter == scene::LightFilter::Trilinear ? 1.0f
                                                              : 2.0f;
  if (d.oversampling > 1) perAxis += 0.5f;
  return std::sqrt(3.0f) * perAxis * d.voxelSize;
}

std::size_t VoxelBox::count() const {
  if (empty()) return 0;
  return static_cast<std::size_t>(hi[0] - lo[0]) * static_cast<std::size_t>(hi[1] - lo[1]) *
         static_cast<std::size_t>(hi[2] - lo[2]);
}

bool VoxelBox::contains(const std::array<int, 3>& v) const {
  for (std::size_t a = 0; a < 3; ++a)
    if (v[a] < lo[a] || v[a] >= hi[a]) return false;
  return true;
}

VoxelBox wholeVolume(const scene::LightsDesc& d) {
  VoxelBox b;
  b.hi = d.voxels;
  return b;
}

namespace {

// A little more than nothing, so float rounding in the planes never drops a voxel or a light.
float slack(const scene::LightsDesc& d) {
  return 0.01f * d.voxelSize;
}

}  // namespace

VoxelBox viewVoxels(const scene::LightsDesc& d, const LightView& view) {
  const scene::Frustum frustum(view.projView);
  const float grow = view.margin + filterReach(d) + slack(d);
  // Twelve half-spaces n.p + w >= 0: the frustum's six grown by `grow`, the volume's six faces.
  std::array<Eigen::Vector4f, 12> planes;
  for (int k = 0; k < 6; ++k) {
    planes[static_cast<std::size_t>(k)] = frustum.planes[static_cast<std::size_t>(k)];
    planes[static_cast<std::size_t>(k)].w() += grow;
  }
  const Vec3 lo = d.origin, hi = d.origin + d.extent();
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector4f low = Eigen::Vector4f::Zero(), high = Eigen::Vector4f::Zero();
    low[a] = 1, low.w() = -lo[a];    // p_a >= lo_a
    high[a] = -1, high.w() = hi[a];  // p_a <= hi_a
    planes[static_cast<std::size_t>(6 + 2 * a)] = low;
    planes[static_cast<std::size_t>(7 + 2 * a)] = high;
  }
  // The clipped solid is convex and bounded (inside the volume): its bounding box is that of its
  // vertices, each where three planes meet and inside all the others.
  Vec3 mn = Vec3::Constant(std::numeric_limits<float>::max()), mx = -mn;
  const float tolerance = 1e-4f * (d.extent().norm() + grow);
  for (std::size_t i = 0; i < 12; ++i)
    for (std::size_t j = i + 1; j < 12; ++j)
      for (std::size_t k = j + 1; k < 12; ++k) {
        Eigen::Matrix3d m;
        m.row(0) = planes[i].head<3>().cast<double>().transpose();
        m.row(1) = planes[j].head<3>().cast<double>().transpose();
        m.row(2) = planes[k].head<3>().cast<double>().transpose();
        if (std::abs(m.determinant()) < 1e-9) continue;
        const Eigen::Vector3d rhs(-planes[i].w(), -planes[j].w(), -planes[k].w());
        const Vec3 p = m.partialPivLu().solve(rhs).cast<float>();
        bool inside = true;
        for (const Eigen::Vector4f& q : planes)
          inside = inside && q.head<3>().dot(p) + q.w() >= -tolerance;
        if (inside) mn = mn.cwiseMin(p), mx = mx.cwiseMax(p);
      }
  VoxelBox b;
  if (mn.x() > mx.x()) return b;  // nothing of the volume in view
  for (int a = 0; a < 3; ++a) {
    const std::size_t s = static_cast<std::size_t>(a);
    // Voxel v's centre is origin + (v + 1/2) h: the voxels with centres in [mn, mx], one more
    // either side.
    const float gLo = (mn[a] - d.origin[a]) / d.voxelSize - 0.5f;
    const float gHi = (mx[a] - d.origin[a]) / d.voxelSize - 0.5f;
    b.lo[s] = std::clamp(static_cast<int>(std::floor(gLo)) - 1, 0, d.voxels[s]);
    b.hi[s] = std::clamp(static_cast<int>(std::ceil(gHi)) + 2, 0, d.voxels[s]);
  }
  return b;
}

ViewCull::ViewCull(const scene::LightsDesc& d, const LightView& view, const VoxelBox& box)
    : frustum_(view.projView),
      reach_(d.range + filterReach(d) + view.margin + slack(d)),
      range_(d.range + slack(d)),
      empty_(box.empty()) {
  for (int a = 0; a < 3; ++a) {
    const std::size_t s = static_cast<std::size_t>(a);
    lo_[a] = d.origin[a] + (static_cast<float>(box.lo[s]) + 0.5f) * d.voxelSize;
    hi_[a] = d.origin[a] + (static_cast<float>(box.hi[s]) - 0.5f) * d.voxelSize;
  }
}

std::vector<sph::lights::LightParticle> lightsInView(
    const scene::LightsDesc& d, const std::vector<sph::lights::LightParticle>& lights,
    const LightView& view, const VoxelBox& box) {
  const ViewCull cull(d, view, box);
  std::vector<sph::lights::LightParticle> kept;
  for (const sph::lights::LightParticle& l : lights)
    if (cull.keeps(l)) kept.push_back(l);
  return kept;
}

}  // namespace sph::render::lights
