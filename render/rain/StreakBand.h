// One band of rows of the streak layer and of the frame's depth, held column by column while the
// band's streaks are drawn (render/rain/StreakRaster.h). Rain streaks are steep on the screen, so
// a streak's consecutive rows are at (nearly) the same x: in rows of the frame they are a layer
// row (15 KB at 960 pixels) apart - a new cache line and, with 4 KiB pages, a new page every row,
// which made the read-modify-write of the layer pixel the raster's hottest instruction
// (docs/notes/2026-11-26-rain-cpu-raster.md, "Toward the 50 ms target"). Column by column, four
// rows of one column share a cache
// line and a column of the band (1 KiB) a page. The pixels and their arithmetic are unchanged:
// only where they are kept, so the layer is the same bit for bit.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "sim/Types.h"

namespace sph::render::rain {

// "Over" in drop order into the layer pixel (L, T) at `p`; alpha 0 leaves it exactly as it was.
inline void blendOver(float* p, const Vec3& c, float alpha) {
  const float kept = 1 - alpha;
  p[0] = p[0] * kept + c.x() * alpha;
  p[1] = p[1] * kept + c.y() * alpha;
  p[2] = p[2] * kept + c.z() * alpha;
  p[3] *= kept;
}

class StreakBand {
 public:
  static constexpr int kRows = 64;  // StreakRaster::kRowsPerBand

  // Starts the band of rows [first, end) (end - first <= kRows) of a `width`-pixel frame: every
  // pixel (L, T) = (0, 0, 0, 1), or with `layer` (row-major, 4 floats a pixel) that layer's
  // pixels; the depth gathered from `frameDepth` (row-major, width a row).
  void begin(int first, int end, int width, const float* frameDepth, const float* layer = nullptr) {
    first_ = first, rows_ = end - first, width_ = width;
    const std::size_t pixels = static_cast<std::size_t>(kRows) * width;
    layer_.resize(4 * pixels), depth_.resize(pixels);
    if (layer == nullptr) {
      for (std::size_t i = 0; i < 4 * pixels; i += 4)
        layer_[i] = layer_[i + 1] = layer_[i + 2] = 0, layer_[i + 3] = 1;
    } else {
      for (int x0 = 0; x0 < width; x0 += kBlock)
        for (int r = 0; r < rows_; ++r) {
          const float* in = layer + 4 * static_cast<std::size_t>(first + r) * width;
          for (int x = x0; x < std::min(x0 + kBlock, width); ++x)
            std::copy(in + 4 * x, in + 4 * x + 4,
                      layer_.data() + 4 * static_cast<std::size_t>(at(x, first + r)));
        }
    }
    // In blocks of columns, so that both the rows read and the columns written stay in cache.
    for (int x0 = 0; x0 < width; x0 += kBlock)
      for (int r = 0; r < rows_; ++r) {
        const float* in = frameDepth + static_cast<std::size_t>(first + r) * width;
        for (int x = x0; x < std::min(x0 + kBlock, width); ++x) depth_[at(x, first + r)] = in[x];
      }
  }

  // The index of pixel (x, row) of the band in layer() (times 4) and depth().
  int at(int x, int row) const { return x * kRows + (row - first_); }
  int firstRow() const { return first_; }
  int width() const { return width_; }
  float* layer() { return layer_.data(); }
  const float* depth() const { return depth_.data(); }

  // Writes the band into its rows of `layer` (row-major, 4 floats a pixel, width a row).
  void store(float* layer) const {
    for (int x0 = 0; x0 < width_; x0 += kBlock)
      for (int r = 0; r < rows_; ++r) {
        float* out = layer + 4 * static_cast<std::size_t>(first_ + r) * width_;
        for (int x = x0; x < std::min(x0 + kBlock, width_); ++x) {
          const float* p = layer_.data() + 4 * static_cast<std::size_t>(at(x, first_ + r));
          out[4 * x] = p[0], out[4 * x + 1] = p[1], out[4 * x + 2] = p[2], out[4 * x + 3] = p[3];
        }
      }
  }

 private:
  static constexpr int kBlock = 16;  // columns of a transposing block: 16 KiB of the band
  std::vector<float> layer_, depth_;
  int first_ = 0, rows_ = 0, width_ = 0;
};

}  // namespace sph::render::rain
