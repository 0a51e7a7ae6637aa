// What the eye sees of the rain space (docs/rain.md, "The visible budget"): a depth image of the
// solids and the water from the rain camera, on the CPU, rebuilt every update. A drop of spawn
// "view" is placed and kept only where it is nearer than the image (rain.occlusion "depth_map"):
// the paper spends the budget on the frustum; in a scene, most of a frustum can be behind a floor
// or a cup, so most of its drops were never seen.
//
// The image is kRows rows over the rain camera's field of view, its columns for the aspect, in
// the frustum's tangent space (x / z, y / z), and holds depths along the camera's forward axis:
// - the solids: a ray from the eye through every pixel corner, out to the far distance, is cut
//   against each solid exactly (Solid::segmentEntry); a pixel takes the nearest of its four
//   corners. Over a pixel a plane's depth lies between its corners' (1/z is affine across the
//   image), so the nearest corner never puts a point of a flat surface's pixel in front of it;
//   a silhouette that crosses a pixel without reaching a corner is missed (edges thinner than a
//   pixel: a 1 cm wall is 1-3 pixels in rain_pour).
// - the water, as its occupied cells (WaterCells, two particle spacings): each cell's box grown by
//   half a cell (a particle's sphere of one spacing anywhere in the cell lies inside it) covers
//   the pixels its eight corners span, at the depth of its nearest corner. Coarse and on the side
//   of hiding: a band about a spacing thick above the water's surface counts as hidden.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/Types.h"
#include "sim/rain/RainSpace.h"
#include "sim/scene/Solid.h"

namespace sph::rain {

class WaterCells;

class EyeDepth {
 public:
  // Rows of the image the rain uses (docs/notes/2026-11-29-rain-visible-budget.md: fewer cost
  // less and hide more of what the eye sees).
  static constexpr int kRows = 64;

  // The image of `solids` and `water` (either may be null) seen from `space`'s eye, `rows` rows;
  // with neither, no image: everything is visible.
  void build(const RainSpace& space, const std::vector<scene::Solid>* solids,
             const WaterCells* water, int rows = kRows);
  // No image: everything visible.
  void clear() { active_ = false; }
  bool active() const { return active_; }
  // Whether p is in front of the image at its pixel (and in front of the eye). True everywhere
  // without an image.
  bool visible(const Vec3& p) const {
    if (!active_) return true;
    const Vec3 d = p - eye_;
    const float z = d.dot(forward_);
    if (!(z > 0)) return false;
    const float inv = 1 / z;
    const float u = std::fma(d.dot(right_) * inv, scaleX_, 0.5f * float(cols_));
    const float v = std::fma(d.dot(up_) * inv, scaleY_, 0.5f * float(rows_));
    const int i = std::min(std::max(static_cast<int>(u), 0), cols_ - 1);
    const int j = std::min(std::max(static_cast<int>(v), 0), rows_ - 1);
    return z < depth_[static_cast<std::size_t>(j) * cols_ + i];
  }
  // The largest depth (m, along forward) any pixel sees to, at most the far distance: nothing
  // beyond it is visible.
  float maxDepth() const { return maxDepth_; }
  int cols() const { return cols_; }
  int rows() const { return rows_; }
  // Per pixel, row by row from the bottom: the depth (m) of the nearest solid or water, or a
  // value beyond far where there is none.
  const std::vector<float>& depths() const { return depth_; }

 private:
  void splatWater(const WaterCells& water, float far);
  bool active_ = false;
  int cols_ = 0, rows_ = kRows;
  Vec3 eye_, forward_, right_, up_;
  float tanRight_ = 0, tanUp_ = 0;
  float scaleX_ = 0, scaleY_ = 0;  // pixels per unit of x / z and of y / z
  float maxDepth_ = 0;
  std::vector<float> corners_;  // (cols + 1) x (rows + 1) corner depths
  std::vector<float> depth_;    // cols x rows pixel depths
};

}  // namespace sph::rain
