// What the rain's CPU path does per pixel after the rasteriser: the far tier's running sums
// (render/rain/StreakSums.h) - lines at the frame's edge and either side of a strip edge, the
// resolve in full and part strips, its exp (render/rain/ExpNear.h), the lists' memory - and the
// composite of the layer over the frame (render/rain/ComposeOver.h). CPU only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#if defined(__AVX512F__)
// GCC 12 warns of the `_mm512_undefined_*()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "render/rain/ComposeOver.h"
#include "render/rain/ExpNear.h"
#include "render/rain/StreakSums.h"
#include "sim/Types.h"

namespace sph::render::rain {
namespace {

// addLines() is add() for each line, set up in groups: also for a slanted line that starts in
// column 0 and leaves the frame on the left within the same column's width (x in (-1, 0) once
// truncated is column 0, yet those rows are off the frame: review of 2026-11-27).
TEST(StreakSums, ALineLeavingTheFrameOnTheLeftAddsOnlyItsRowsInside) {
  constexpr int kW = 8, kH = 40;
  const std::vector<float> depth(kW * kH, 1.0f);
  Lines lines{};
  lines.xt[0] = 0.6f, lines.yt[0] = 10, lines.zt[0] = 0.5f, lines.dx[0] = -1, lines.dz[0] = 0;
  lines.invDy[0] = 1.0f / 20, lines.coverage[0] = 0.5f;
  lines.first[0] = 10, lines.end[0] = 30, lines.ok[0] = 1;
  const Vec3 colour(0.8f, 0.6f, 0.4f);
  const float alpha = 0.25f;
  auto layerOf = [&](bool grouped, std::uint64_t& fragments) {
    StreakSums sums;
    sums.begin(kW, kH, depth.data(), 1);
    fragments = grouped ? sums.addLines(0, lines, 1, &colour, &alpha)
                        : sums.add(0, lines[0], 10, 30, colour, alpha);
    std::vector<float> layer(4 * kW * kH);
    sums.resolve(layer.data());
    return layer;
  };
  std::uint64_t groupedFragments = 0, oneFragments = 0;
  const std::vector<float> grouped = layerOf(true, groupedFragments);
  const std::vector<float> one = layerOf(false, oneFragments);
  EXPECT_EQ(groupedFragments, oneFragments);
  EXPECT_LT(oneFragments, 20u);  // the rows from x < 0 on are off the frame
  EXPECT_EQ(grouped, one);
}

// A line half a pixel wide from (x, first) over rows [first, end), moving dx columns over them,
// at depth 0.5.
Line lineOver(float x, float dx, int first, int end) {
  Line l{};
  l.xt = x, l.yt = static_cast<float>(first), l.zt = 0.5f, l.dx = dx, l.dz = 0;
  l.invDy = 1.0f / static_cast<float>(end - first), l.coverage = 0.5f;
  l.first = first, l.end = end;
  return l;
}

// The runs are listed per strip of columns and added strip by strip (StreakSums.h): straight
// lines in the columns either side of strip edges, one running on to the last row, and a line
// slanted across an edge, against each pixel's value worked out by hand - T = exp(-sum b) of the
// lines over it, L = their colour times 1 - T - and (0, 0, 0, 1) everywhere else.
TEST(StreakSums, RunsEitherSideOfAStripEdgeLandInTheirOwnPixels) {
  constexpr int kW = 100, kH = 30;
  const std::vector<float> depth(kW * kH, 1.0f);
  const Vec3 colour(0.8f, 0.6f, 0.4f);
  const float alpha = 0.25f;
  StreakSums sums;
  sums.begin(kW, kH, depth.data(), 2);
  // Columns 31 | 32 and 63 | 64; the last one from row 20 to the top.
  std::uint64_t fragments = sums.add(0, lineOver(31.5f, 0, 2, 12), 2, 12, colour, alpha);
  fragments += sums.add(1, lineOver(32.5f, 0, 5, 15), 5, 15, colour, alpha);
  fragments += sums.add(0, lineOver(63.5f, 0, 0, 10), 0, 10, colour, alpha);
  fragments += sums.add(1, lineOver(64.5f, 0, 20, kH), 20, kH, colour, alpha);
  // From column 62 to column 65 over rows 10..22: across the edge at 64.
  fragments += sums.add(0, lineOver(62.2f, 3, 10, 22), 10, 22, colour, alpha);
  std::vector<float> layer(4 * kW * kH);
  sums.resolve(layer.data());
  EXPECT_EQ(fragments, 10u + 10u + 10u + 10u + 12u);
  EXPECT_EQ(sums.runs(), 4u + 4u);    // the slanted line: one run in each of its 4 columns
  std::vector<int> over(kW * kH, 0);  // lines over each pixel
  auto cover = [&](int x, int first, int end) {
    for (int y = first; y < end; ++y) ++over[static_cast<std::size_t>(y) * kW + x];
  };
  cover(31, 2, 12), cover(32, 5, 15), cover(63, 0, 10), cover(64, 20, kH);
  for (int y = 10; y < 22; ++y) {  // the slanted line's column in row y, as add() takes it
    const float s = (static_cast<float>(y) + 0.5f - 10) / 12;
    cover(static_cast<int>(62.2f + 3 * s), y, y + 1);
  }
  const float b = -std::log(1 - alpha);
  for (std::size_t p = 0; p < over.size(); ++p) {
    const float t = std::exp(-b * static_cast<float>(over[p]));
    EXPECT_NEAR(layer[4 * p + 3], t, 2e-4f) << p;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(layer[4 * p + k], colour[k] * (1 - t), 2e-4f) << p;
  }
}

// The resolve's exp (render/rain/ExpNear.h) at every x = -w 2^-18 the sums give for w up to
// 2^23 (T down to exp(-32)) in steps of 7, and past the clamp: within 2 ulp of std::exp, exp(0) = 1
// exactly, and the lanes the same bits as one at a time.
TEST(StreakSums, TheResolvesExpIsWithinTwoUlpAndTheLanesGiveTheSameBits) {
  std::vector<float> xs;
  for (std::int32_t w = 0; w < (1 << 23); w += 7) xs.push_back(static_cast<float>(w) * -0x1p-18f);
  for (float x : {-80.0f, -86.9f, -87.0f, -90.0f, -500.0f}) xs.push_back(x);
  while (xs.size() % 16 != 0) xs.push_back(0);
  EXPECT_EQ(expNear(0.0f), 1.0f);
  float worst = 0;
  for (float x : xs) {
    const float e = expNear(x), exact = std::exp(std::max(x, -87.0f));
    worst = std::max(worst, std::abs(e - exact) / (std::nextafter(exact, 2.0f) - exact));
  }
  EXPECT_LE(worst, 2.0f);
  EXPECT_LT(expNear(-500.0f), 2e-38f);
#if defined(__AVX512F__)
  for (std::size_t i = 0; i < xs.size(); i += 16) {
    alignas(64) float lanes[16];
    _mm512_store_ps(lanes, expNear(_mm512_loadu_ps(xs.data() + i)));
    for (int k = 0; k < 16; ++k) ASSERT_EQ(lanes[k], expNear(xs[i + k])) << xs[i + k];
  }
#endif
}

// A frame 40 columns wide: a strip of 32 and one of 8 (the lanes' masked tail). Column x gets
// lines(x) lines over rows [x % 32, 40): every pixel against its T = (1 - a)^lines and L = c (1 -
// T), and columns 3 and 35 - the same lines, in the full strip and in the tail - the same bits.
TEST(StreakSums, TheResolveWritesEachPixelsSumsInFullAndPartStrips) {
  constexpr int kW = 40, kH = 40;
  const auto lines = [](int x) { return x < 32 ? x + 1 : x - 31; };  // column 35 as column 3
  const std::vector<float> depth(kW * kH, 1.0f);
  std::vector<float> layer(4 * kW * kH, -1.0f);
  {
    StreakSums sums;
    sums.begin(kW, kH, depth.data(), 1);
    for (int x = 0; x < kW; ++x)
      for (int k = 0; k < lines(x); ++k)
        sums.add(0, lineOver(static_cast<float>(x) + 0.5f, 0, x % 32, kH), x % 32, kH,
                 Vec3(0.8f, 0.6f, 0.4f), 0.125f);
    sums.resolve(layer.data());
  }
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float* q = layer.data() + 4 * (static_cast<std::size_t>(y) * kW + x);
      const int over = y >= x % 32 ? lines(x) : 0;
      const float t = std::pow(1 - 0.125f, static_cast<float>(over));
      const float bound = 2e-4f * static_cast<float>(over);
      EXPECT_NEAR(q[3], t, bound) << x << " " << y;
      EXPECT_NEAR(q[0], 0.8f * (1 - t), bound) << x << " " << y;
      EXPECT_NEAR(q[1], 0.6f * (1 - t), bound) << x << " " << y;
      EXPECT_NEAR(q[2], 0.4f * (1 - t), bound) << x << " " << y;
      if (over == 0) {
        EXPECT_EQ(std::vector<float>(q, q + 4), (std::vector<float>{0, 0, 0, 1}));
      }
    }
  for (int y = 0; y < kH; ++y)
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(layer[4 * (static_cast<std::size_t>(y) * kW + 3) + k],
                layer[4 * (static_cast<std::size_t>(y) * kW + 35) + k])
          << y;
}

// The CPU composite (render/rain/ComposeOver.h) over 1,027 pixels (the lanes take 4 at a time, the
// last 3 one at a time): each channel within rounding of 255 L + T c (exactly at most a few in a
// thousand off by one, at a half), clamped, the alpha kept, pixels no streak covers unchanged, and
// the tail's pixels - copies of the first three - the same bytes as the lanes gave them.
TEST(ComposeOver, EachChannelIsTheLayerOverTheFrameRoundedAndTheAlphaKept) {
  constexpr int kPixels = 1027;
  std::vector<float> layer(4 * kPixels);
  std::vector<std::uint8_t> rgba(4 * kPixels);
  std::uint32_t state = 12345;
  const auto next = [&state]() { return state = state * 1664525u + 1013904223u, state >> 8; };
  for (int p = 0; p < kPixels; ++p) {
    const float t = static_cast<float>(next() % 1001) / 1000.0f;
    for (int k = 0; k < 3; ++k)
      layer[4 * p + k] = (1 - t) * static_cast<float>(next() % 1001) / 1000.0f;
    layer[4 * p + 3] = t;
    for (int k = 0; k < 4; ++k) rgba[4 * p + k] = static_cast<std::uint8_t>(next());
  }
  for (int p : {5, 6, 7})
    layer[4 * p] = layer[4 * p + 1] = layer[4 * p + 2] = 0, layer[4 * p + 3] = 1;
  layer[4 * 8] = 1.0f, layer[4 * 8 + 3] = 1.0f, rgba[4 * 8] = 255;  // over 255: clamped
  for (int k = 0; k < 12; ++k)  // the tail: copies of pixels 0, 1, 2
    layer[4 * (kPixels - 3) + k] = layer[k], rgba[4 * (kPixels - 3) + k] = rgba[k];
  const std::vector<std::uint8_t> before = rgba;
  composeOver(layer, rgba);
  int offByOne = 0;
  for (int p = 0; p < kPixels; ++p) {
    EXPECT_EQ(rgba[4 * p + 3], before[4 * p + 3]) << p;
    for (int k = 0; k < 3; ++k) {
      const double v = 255.0 * layer[4 * p + k] + double{layer[4 * p + 3]} * before[4 * p + k];
      const double expected = std::floor(std::clamp(v, 0.0, 255.0) + 0.5);
      EXPECT_NEAR(rgba[4 * p + k], expected, 1.0) << p << " " << k;
      offByOne += rgba[4 * p + k] != expected;
    }
  }
  EXPECT_LE(offByOne, 3 * kPixels / 100);
  for (int p : {5, 6, 7})
    for (int k = 0; k < 4; ++k) EXPECT_EQ(rgba[4 * p + k], before[4 * p + k]);
  EXPECT_EQ(rgba[4 * 8], 255);
  for (int k = 0; k < 12; ++k) EXPECT_EQ(rgba[4 * (kPixels - 3) + k], rgba[k]) << k;
}

// A list more than four times larger than its last frame's runs gives its memory back at the next
// frame: after a frame of 20,000 runs in one strip, then frames of one run, the lists hold room
// for a few runs, not 20,000 (review of 2026-11-27: memory was every list's peak).
TEST(StreakSums, AListFarLargerThanItsLastFramesRunsGivesItsMemoryBack) {
  constexpr int kW = 64, kH = 8;
  const std::vector<float> depth(kW * kH, 1.0f);
  const Vec3 colour(0.8f, 0.6f, 0.4f);
  std::vector<float> layer(4 * kW * kH);
  StreakSums sums;
  auto frame = [&](int lines) {
    sums.begin(kW, kH, depth.data(), 1);
    for (int i = 0; i < lines; ++i) sums.add(0, lineOver(5.5f, 0, 0, 1), 0, 1, colour, 0.01f);
    sums.resolve(layer.data());
    EXPECT_EQ(sums.runs(), static_cast<std::size_t>(lines));
  };
  frame(20000);
  EXPECT_GE(sums.runCapacity(), 20000u);
  frame(20000);  // a steady frame keeps its room: no allocation
  EXPECT_GE(sums.runCapacity(), 20000u);
  frame(1), frame(1);
  EXPECT_LT(sums.runCapacity(), 4096u);
  EXPECT_NEAR(layer[4 * (0 * kW + 5) + 3], 0.99f, 1e-3f);  // the one line still drawn
}

}  // namespace
}  // namespace sph::render::rain
