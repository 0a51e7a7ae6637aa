// The CPU path's composite (rain.draw "cpu", RainRenderer::drawCpu): the streaks' layer over the
// frame's 8-bit colour, read back from GL and written back by a blit.
#pragma once

#include <cstdint>
#include <vector>

namespace sph::render::rain {

// frame = L + T frame for the layer (StreakRaster::layer(): 4 floats a pixel, L sRGB-encoded in
// [0, 1], T) over `rgba` (row-major, 4 bytes a pixel, sRGB-encoded), in place, each channel
// fma(T, c, 255 L) clamped to [0, 255] and rounded to the nearest; the alpha is kept. A pixel no
// streak covers, (0, 0, 0, 1), keeps its bytes exactly. In AVX-512 lanes where the build has them
// (the same operations: the same bytes), in parallel.
void composeOver(const std::vector<float>& layer, std::vector<std::uint8_t>& rgba);

}  // namespace sph::render::rain
