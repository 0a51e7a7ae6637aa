// The lines of the level of detail (rain.lod_width, docs/rain.md, "Level of detail"): a streak
// narrower than lod_width pixels drawn as one sample per row, blended into a band of the layer
// (render/rain/StreakBand.h). Set up by StreakRaster (render/rain/StreakRaster.cpp, setUpLine).
#pragma once

#include <cstdint>

#include <vector>

#include "render/rain/StreakBand.h"
#include "render/rain/StreakFrame.h"
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

// The lines of the level of detail (render/rain/StreakLine.h) of up to 16 drops at once, in SIMD
// lanes: the set-up of a line is a dozen divisions and a square root, which one drop at a time
// took as long as drawing its rows in lanes (docs/notes/2026-11-26-rain-cpu-raster.md, "The
// lines and their set-up in SIMD lanes"). A lane whose
// streak is drawn exact (through the near or far plane, flat or short on the screen, or not
// narrower than lod_width) is not `ok`.
struct Lines {
  static constexpr int kLanes = 16;
  alignas(64) float xt[kLanes], yt[kLanes], zt[kLanes], dx[kLanes], dz[kLanes];
  alignas(64) float invDy[kLanes], coverage[kLanes];
  alignas(64) int first[kLanes], end[kLanes], ok[kLanes];
  Line operator[](int k) const {
    return {xt[k], yt[k], zt[k], dx[k], dz[k], invDy[k], coverage[k], first[k], end[k]};
  }
};

// Sets up the lines of the `count` (<= 16) drops `drops` of `heads` in `f`; lanes past `count`
// repeat the last drop.
void setUpLines(const detail::Frame& f, const std::vector<Vec3>& heads, const std::uint32_t* drops,
                int count, float lodWidth, Lines& l);

// Blends rows [first, end) of `line` (within the band `b`) in colour `c`, the streak image's
// profile `profile` (padded rows, `fh` unpadded) along it; returns the fragments that passed the
// depth test. `simd`: 16 rows at a time with AVX-512 where the build has it (the same bits as
// one row at a time, which a build without it and `simd` false run - with this compiler: the
// scalar rows' bits depend on which products GCC 12 fuses with a sum at -O3 -march=native, which
// another compiler or flag set may change;
// StreakRaster.LinesInSimdLanesGiveTheSameLayerAsOneRowAtATime checks it in each build).
std::uint64_t drawLineRows(const Line& line, int first, int end, StreakBand& b, const Vec3& c,
                           const float* profile, float fh, bool simd);

}  // namespace sph::render::rain
