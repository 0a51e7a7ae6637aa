// The rain's streaks rasterised on the CPU (OpenMP), for llvmpipe: it spends 1-2 us of setup on
// every triangle however few pixels it covers, so 1,000,000 streaks of ~15 pixels took 2.1 s a
// frame as triangles (docs/notes/2026-11-26-rain-cpu-raster.md, "Drawing: where the time
// goes"). This draws the same
// streaks - a camera-facing quad from where the drop was one exposure ago to where it is, sampled
// at the pixel centres inside it, its streak image filtered bilinearly at the perspective-correct
// coordinates, depth tested against the frame - into a float layer that RainRenderer composes
// over the frame's colour (render/rain/RainRenderer.h). No GL here, so it is tested without it.
//
// Order: every pixel composes its fragments in drop order, as the triangles blended them, so
// the picture differs from theirs only by rounding (GL rounds the RGBA8 frame after every blend,
// this once at the end). Work is split into bands of rows, each band walking the drops in order:
// no two threads touch a pixel, and the layer is the same bit for bit for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/rain/StreakBand.h"
#include "render/rain/StreakImages.h"
#include "render/rain/StreakSums.h"
#include "sim/scene/Camera.h"
#include "sim/scene/RainDesc.h"

namespace sph::render::rain {

// What the rasteriser needs of the camera: its matrices and a viewport of width x height pixels.
struct StreakView {
  scene::CameraFrame camera;
  int width = 0, height = 0;
};

// The drops of one frame; all fall with one velocity (sim/rain/RainSystem.h).
struct StreakDrops {
  const std::vector<Vec3>* positions = nullptr;       // m, the heads
  const std::vector<std::uint8_t>* layers = nullptr;  // streak image per drop
  Vec3 velocity = Vec3::Zero();                       // m/s
};

class StreakRaster {
 public:
  // Rows of a band: large enough that most streaks (~26 rows at 960x540 for the default rain)
  // are set up once (a streak is set up again in every band it crosses), small enough that a
  // band's layer and depth (1.2 MB at 960 pixels a row) mostly stay in a core's cache and that
  // 2 threads share 9 bands evenly. 32 rows took ~10% longer, 135 the same (1M drops, 1 thread).
  static constexpr int kRowsPerBand = StreakBand::kRows;

  // `desc`: the streak's exposure and width and the spotlight; `images`: the streak images.
  StreakRaster(const scene::RainDesc& desc, StreakImages images);

  // Rasterises the drops into layer(). `unlit`: the linear colour of a drop outside the
  // spotlight's cone (eq. (13)). `depth`: the frame's window depth per pixel (width x height,
  // row 0 at the bottom, GL's order), a fragment is kept where it is nearer (GL_LESS); null:
  // no depth test. With desc.lodWidth > 0, streaks narrower than that many pixels are drawn as
  // lines of one sample per row instead, or with desc.farTier "sums" added once per column into
  // running sums (render/rain/StreakSums.h; docs/rain.md, "Level of detail").
  void draw(const StreakView& view, const StreakDrops& drops, const Vec3& unlit,
            const float* depth);

  // Per pixel, row 0 at the bottom: (L.r, L.g, L.b, T), what the streaks make of a pixel of
  // colour d is L + T d (colours sRGB-encoded in [0, 1] like the frame's; GL's blend
  // GL_ONE, GL_SRC_ALPHA).
  const std::vector<float>& layer() const { return layer_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // Fragments that passed the depth test in the last draw (what GL_SAMPLES_PASSED counted).
  std::uint64_t fragments() const { return fragments_; }
  // The lines of the level of detail 16 rows at a time in AVX-512 lanes (default, where the
  // build has AVX-512) or one row at a time (false): the same layer, bit for bit; for tests and
  // benchmarks.
  void setSimd(bool simd) { simd_ = simd; }

 private:
  scene::RainDesc desc_;
  StreakImages images_;
  std::vector<float> alpha_;    // images_ as floats in [0, 1], each padded by its edge texels
  std::vector<float> profile_;  // alpha_'s rows averaged across the width (rain.lod_width)
  std::vector<float> layer_;
  std::vector<float> farDepth_;  // the frame's depth when draw() is given none: beyond every streak
  // The drops each band of rows takes, per thread of the binning pass (its own contiguous share
  // of the drops): bins_[thread * bands + band], in drop order.
  std::vector<std::vector<std::uint32_t>> bins_;
  std::vector<StreakBand> bands_;  // per thread: the band it draws, column by column
  StreakSums sums_;                // rain.far_tier "sums": the far tier's lines
  int width_ = 0, height_ = 0;
  std::uint64_t fragments_ = 0;
  bool simd_ = true;
};

}  // namespace sph::render::rain
