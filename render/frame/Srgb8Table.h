// The 8-bit sRGB code of a linear colour component, as the GL shaders' toSrgb() written to an
// RGBA8 target gives it (clamped to [0, 1], encoded, rounded to the nearest code), without a
// pow() a channel: for the lights.shade "cpu" pass, which encodes every lit pixel of the frame
// (render/lights/CpuShading.cpp). The codes' thresholds (the linear value where each code begins)
// and, for 4,096 equal bins of [0, 1], the code at each bin's start: a bin holds at most one
// threshold (the encoding rises by at most 12.92 x 255 / 4,096 = 0.8 codes a bin), so one table
// look-up and at most one comparison give the code. Agrees with toSrgb8 (Lighting.h) but where a
// value lies within float rounding of a threshold: tests/test_srgb8_table.cpp.
#pragma once

#include <array>
#include <cstdint>

namespace sph::render::frame {

class Srgb8Table {
 public:
  Srgb8Table();
  std::uint8_t operator()(float c) const {
    if (!(c > 0.0f)) return 0;  // NaN too, as GL's clamp of a NaN
    if (c >= 1.0f) return 255;
    const int bin = static_cast<int>(c * kBins);
    int k = start_[static_cast<std::size_t>(bin)];
    if (k < 255 && c >= threshold_[static_cast<std::size_t>(k) + 1]) ++k;
    return static_cast<std::uint8_t>(k);
  }

 private:
  static constexpr int kBins = 4096;
  std::array<std::uint8_t, kBins + 1> start_{};
  std::array<float, 256> threshold_{};  // threshold_[k]: the least linear value of code k
};

// One table for the process (made on first use; const after).
const Srgb8Table& srgb8Table();

}  // namespace sph::render::frame
