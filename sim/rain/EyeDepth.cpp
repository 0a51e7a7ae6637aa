#include "sim/rain/EyeDepth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/rain/RainSystem.h"

namespace sph::rain {

void EyeDepth::build(const RainSpace& s, const std::vector<scene::Solid>* solids,
                     const WaterCells* water, int rows) {
  const bool anySolid = solids && !solids->empty();
  const bool anyWater = water && water->size() > 0;
  active_ = anySolid || anyWater;
  if (!active_) return;
  rows_ = rows;
  eye_ = s.eye, forward_ = s.forward, right_ = s.right, up_ = s.up;
  tanRight_ = s.tanRight, tanUp_ = s.tanUp;
  cols_ = std::clamp(static_cast<int>(std::lround(rows_ * s.tanRight / s.tanUp)), 1, 8 * rows_);
  scaleX_ = 0.5f * float(cols_) / s.tanRight, scaleY_ = 0.5f * float(rows_) / s.tanUp;
  // Beyond far: nothing there, and no drop is further.
  const float none = 2 * s.far;
  const std::size_t w = static_cast<std::size_t>(cols_) + 1;
  corners_.assign(w * (rows_ + 1), none);
  depth_.assign(static_cast<std::size_t>(cols_) * rows_, none);
  if (anySolid) {
    const auto cornerRows = static_cast<std::ptrdiff_t>(rows_ + 1);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t j = 0; j < cornerRows; ++j) {
      const float y = (2 * float(j) / float(rows_) - 1) * s.tanUp;
      for (std::size_t i = 0; i < w; ++i) {
        const float x = (2 * float(i) / float(cols_) - 1) * s.tanRight;
        // The ray to depth far: its share of the way to the first solid is that share of far.
        const Vec3 end = s.eye + s.far * (s.forward + x * s.right + y * s.up);
        const float t = firstSolidEntry(s.eye, end, *solids);
        if (t <= 1) corners_[static_cast<std::size_t>(j) * w + i] = t * s.far;
      }
    }
    for (int j = 0; j < rows_; ++j)
      for (int i = 0; i < cols_; ++i) {
        const std::size_t c = static_cast<std::size_t>(j) * w + i;
        depth_[static_cast<std::size_t>(j) * cols_ + i] =
            std::min({corners_[c], corners_[c + 1], corners_[c + w], corners_[c + w + 1]});
      }
  }
  if (anyWater) splatWater(*water, s.far);
  maxDepth_ = std::min(s.far, *std::max_element(depth_.begin(), depth_.end()));
}

void EyeDepth::splatWater(const WaterCells& water, float far) {
  const float cell = water.cell();
  const float margin = 0.5f * cell;
  const Vec3 size = Vec3::Constant(cell + 2 * margin);
  // A box that reaches behind the eye is clipped at depth kNearest: the pixels it covers are
  // those of its part in front, whose corners are the box's corners there and the points where
  // its edges cross that depth (a convex part projects onto the hull of its corners').
  constexpr float kNearest = 1e-5f;  // m
  static constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                        {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  water.forEachCorner([&](const Vec3& corner) {
    const Vec3 lo = corner - Vec3::Constant(margin);
    float zMin = std::numeric_limits<float>::max(), zMax = -zMin;
    Vec3 q[8];  // the corners in camera coordinates: right, up, forward
    for (int k = 0; k < 8; ++k) {
      const Vec3 p = lo + Vec3(k & 1 ? size.x() : 0, k & 2 ? size.y() : 0, k & 4 ? size.z() : 0);
      q[k] = Vec3((p - eye_).dot(right_), (p - eye_).dot(up_), (p - eye_).dot(forward_));
      zMin = std::min(zMin, q[k].z()), zMax = std::max(zMax, q[k].z());
    }
    if (zMax < kNearest || zMin >= far) return;  // behind the eye, or beyond every drop
    float uMin = std::numeric_limits<float>::max(), uMax = -uMin, vMin = uMin, vMax = -uMin;
    auto extend = [&](const Vec3& c) {
      uMin = std::min(uMin, c.x() / c.z()), uMax = std::max(uMax, c.x() / c.z());
      vMin = std::min(vMin, c.y() / c.z()), vMax = std::max(vMax, c.y() / c.z());
    };
    for (const Vec3& c : q)
      if (c.z() >= kNearest) extend(c);
    if (zMin < kNearest) {
      for (const auto& e : kEdges) {
        const Vec3 &a = q[e[0]], &b = q[e[1]];
        if ((a.z() < kNearest) == (b.z() < kNearest)) continue;
        const float t = (kNearest - a.z()) / (b.z() - a.z());
        extend(Vec3(a + t * (b - a)));
      }
    }
    auto pixel = [](float t, float scale, int n) {  // clamped before the cast
      const float f = std::floor(std::fma(t, scale, 0.5f * float(n)));
      return static_cast<int>(std::clamp(f, -1.0f, float(n)));
    };
    const int i0 = std::max(0, pixel(uMin, scaleX_, cols_));
    const int i1 = std::min(cols_ - 1, pixel(uMax, scaleX_, cols_));
    const int j0 = std::max(0, pixel(vMin, scaleY_, rows_));
    const int j1 = std::min(rows_ - 1, pixel(vMax, scaleY_, rows_));
    const float z = std::max(zMin, kNearest);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        float& d = depth_[static_cast<std::size_t>(j) * cols_ + i];
        d = std::min(d, z);
      }
  });
}

}  // namespace sph::rain
