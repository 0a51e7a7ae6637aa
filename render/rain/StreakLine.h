// The lines of the level of detail (rain.lod_width, docs/rain.md, "Level of detail"): a streak
// narrower than lod_width pixels drawn as one sample per row, blended into a band of the layer
// (render/rain/StreakBand.h). Set up by StreakRaster (render/rain/StreakRaster.cpp, setUpLine).
#pragma once

#include <cstdint>

#include "render/rain/StreakBand.h"
#include "sim/Types.h"

namespace sph::render::rain {

// A streak narrower than lod_width pixels, wholly between near and far and steeper than 45
// degrees on the screen, drawn as a line of one sample per row - at the centre line, with the
// streak image averaged across its width and weighted by the share of the row the streak covers,
// its coordinate along the streak and its depth interpolated affinely between the ends (no
// perspective divide). The exact quads cover a pixel centre in about that share of the rows, at
// full alpha: the same light on average, spread evenly, in ~1/4 of the work per row.
struct Line {
  float xt, yt, zt;  // the tail in window coordinates (pixels, depth)
  float dx, dz;      // the head minus the tail, per unit of s
  float invDy;       // s = (y - yt) invDy: 0 at the tail, 1 at the head
  float coverage;    // share of a row the streak covers, < 1
  int first, end;    // rows whose centre lies between the ends
};

// Blends rows [first, end) of `line` (within the band `b`) in colour `c`, the streak image's
// profile `profile` (padded rows, `fh` unpadded) along it; returns the fragments that passed the
// depth test. `simd`: 16 rows at a time with AVX-512 where the build has it (the same bits as
// one row at a time, which a build without it and `simd` false run).
std::uint64_t drawLineRows(const Line& line, int first, int end, StreakBand& b, const Vec3& c,
                           const float* profile, float fh, bool simd);

}  // namespace sph::render::rain
