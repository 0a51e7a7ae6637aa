// The rain's true picture, against which each way of drawing it (rain.lod_width, rain.far_tier;
// docs/rain.md, "The default: the sums at lod_width 8") is measured by the test
// StreakRaster.TheDefaultIsCloserToTheTruePictureThanTheExactStreaks and by bench/rain_truth.cpp:
// the exact streaks drawn at `scale` times the resolution and box-filtered down, scale x scale
// pixels to one. At 1x the exact path samples a streak narrower than a pixel at the pixel centres
// it happens to cover, at full alpha: a dotted line that the finer frame spreads over its pixels.
// The box filter averages the 8-bit frame's sRGB-encoded values, as a multisampled GL frame
// without sRGB blending resolves them. No GL: the CPU rasteriser and composite of rain.draw "cpu"
// (render/rain/StreakRaster.h, render/rain/ComposeOver.h), as RainRenderer::drawCpu uses them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "render/rain/ComposeOver.h"
#include "render/rain/StreakImages.h"
#include "render/rain/StreakRaster.h"
#include "sim/rain/RainSystem.h"

namespace sph::test::truth {

// The drops of `r` as the rasteriser takes them.
inline render::rain::StreakDrops dropsOf(const rain::RainSystem& r) {
  return render::rain::StreakDrops{&r.positions(), &r.layers(), r.velocity()};
}

// Means of scale x scale pixels of a width x height RGB image.
inline std::vector<double> boxFiltered(const std::vector<double>& rgb, int width, int height,
                                       int scale) {
  const int w = width / scale, h = height / scale;
  std::vector<double> out(3 * static_cast<std::size_t>(w) * h, 0.0);
  for (int y = 0; y < h * scale; ++y)
    for (int x = 0; x < w * scale; ++x)
      for (int k = 0; k < 3; ++k)
        out[3 * (static_cast<std::size_t>(y / scale) * w + x / scale) + k] +=
            rgb[3 * (static_cast<std::size_t>(y) * width + x) + k];
  for (double& v : out) v /= scale * scale;
  return out;
}

// `drops` drawn, in their order, with `d`'s settings at width x height over a frame of one colour
// (sRGB-encoded bytes), box-filtered scale x scale to one: RGB values in [0, 255], row 0 at the
// bottom, (width / scale) x (height / scale) pixels.
inline std::vector<double> frame(const scene::RainDesc& d, const render::rain::StreakDrops& drops,
                                 const scene::CameraFrame& camera, int width, int height, int scale,
                                 const Vec3& unlit, const std::uint8_t background[3]) {
  // RainRenderer's streak images: 16 x 64 texels.
  render::rain::StreakRaster raster(
      d, render::rain::generateStreakImages(d.streakLayers, 16, 64, d.seed));
  raster.draw(render::rain::StreakView{camera, width, height}, drops, unlit, nullptr);
  std::vector<std::uint8_t> rgba(4 * static_cast<std::size_t>(width) * height);
  for (std::size_t p = 0; p < rgba.size() / 4; ++p) {
    for (int k = 0; k < 3; ++k) rgba[4 * p + k] = background[k];
    rgba[4 * p + 3] = 255;
  }
  render::rain::composeOver(raster.layer(), rgba);
  std::vector<double> rgb(3 * rgba.size() / 4);
  for (std::size_t p = 0; p < rgba.size() / 4; ++p)
    for (int k = 0; k < 3; ++k) rgb[3 * p + k] = rgba[4 * p + k];
  return boxFiltered(rgb, width, height, scale);
}

// The true picture: the exact streaks (rain.lod_width 0) at `scale` x the resolution, filtered.
inline std::vector<double> reference(scene::RainDesc d, const render::rain::StreakDrops& drops,
                                     const scene::CameraFrame& camera, int width, int height,
                                     int scale, const Vec3& unlit,
                                     const std::uint8_t background[3]) {
  d.lodWidth = 0;
  return frame(d, drops, camera, width * scale, height * scale, scale, unlit, background);
}

// PSNR of `a` against `b`, values in [0, 255].
inline double psnr(const std::vector<double>& a, const std::vector<double>& b) {
  double se = 0;
  for (std::size_t i = 0; i < a.size(); ++i) se += (a[i] - b[i]) * (a[i] - b[i]);
  return 10 * std::log10(255.0 * 255.0 / std::max(se / static_cast<double>(a.size()), 1e-12));
}

// Means of 4 x 4 pixels of a width x height RGB image: the picture at a scale of a few pixels.
inline std::vector<double> blocks(const std::vector<double>& rgb, int width, int height) {
  return boxFiltered(rgb, width, height, 4);
}

// The streaks' light: the summed distance of the values from the background's.
inline double light(const std::vector<double>& rgb, const std::uint8_t background[3]) {
  double s = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) s += std::abs(rgb[i] - background[i % 3]);
  return s;
}

}  // namespace sph::test::truth
