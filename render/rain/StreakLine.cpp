#include "render/rain/StreakLine.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#if defined(__AVX512F__)
#include <immintrin.h>
// GCC 12 warns of the `_mm512_undefined_ps()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace sph::render::rain {

using detail::applyRow;
using detail::floorToInt;
using detail::Vec4f;

namespace {

// One row at a time. The AVX-512 path below repeats this arithmetic operation for operation -
// which products GCC fuses with the following sum here (z, the texel row, the fetch and the
// blend) and which not (x) included - so that both give the same bits
// (StreakRaster.LinesInSimdLanesGiveTheSameLayerAsOneRowAtATime).
std::uint64_t rowsOneByOne(const Line& line, int first, int end, StreakBand& b, const Vec3& c,
                           const float* p, float fh) {
  std::uint64_t fragments = 0;
  float* const out = b.layer();
  const float* const depth = b.depth();
  const float width = static_cast<float>(b.width());
  for (int row = first; row < end; ++row) {
    const float sAlong =
        std::min(std::max(0.0f, (static_cast<float>(row) + 0.5f - line.yt) * line.invDy), 1.0f);
    const float x = line.xt + sAlong * line.dx;
    if (!(x >= 0 && x < width)) continue;
    const int pixel = b.at(static_cast<int>(x), row);
    const float z = line.zt + sAlong * line.dz;
    const bool keep = z < depth[pixel];
    const float tt = sAlong * fh + 0.5f;  // padded texel rows, as the exact streaks' fetch
    const int t0 = static_cast<int>(tt);
    const float a = p[t0] + (tt - static_cast<float>(t0)) * (p[t0 + 1] - p[t0]);
    fragments += keep;
    blendOver(out + 4 * static_cast<std::size_t>(pixel), c, keep ? a * line.coverage : 0.0f);
  }
  return fragments;
}

#if defined(__AVX512F__)
// 16 rows a step. Rain falls nearly straight down, so the 16 rows of a step are mostly in one
// column of the band, i.e. 16 consecutive pixels of its column-major layer (StreakBand.h): their
// depth is one load and their (L, T) four, blended in lanes. Steps whose rows are in several
// columns blend one row at a time. `_round` products and sums are not fused by the compiler,
// `fmadd` is: the operations of rowsOneByOne, in the same order.
std::uint64_t rowsInLanes(const Line& line, int first, int end, StreakBand& b, const Vec3& c,
                          const float* p, float fh) {
  constexpr int kNear = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
  // Each bit of a 4-bit mask (4 pixels) spread over the 4 floats of its pixel.
  static constexpr std::uint16_t kSpread[16] = {0x0000, 0x000f, 0x00f0, 0x00ff, 0x0f00, 0x0f0f,
                                                0x0ff0, 0x0fff, 0xf000, 0xf00f, 0xf0f0, 0xf0ff,
                                                0xff00, 0xff0f, 0xfff0, 0xffff};
  std::uint64_t fragments = 0;
  float* const out = b.layer();
  const float* const depth = b.depth();
  const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f);
  const __m512 half = _mm512_set1_ps(0.5f), width = _mm512_set1_ps(static_cast<float>(b.width()));
  const __m512 colour = _mm512_setr_ps(c.x(), c.y(), c.z(), 0, c.x(), c.y(), c.z(), 0, c.x(), c.y(),
                                       c.z(), 0, c.x(), c.y(), c.z(), 0);
  alignas(64) int pixels[16];
  alignas(64) float alphas[16];
  for (int row0 = first; row0 < end; row0 += 16) {
    const __mmask16 active =
        end - row0 >= 16 ? __mmask16(0xffff) : __mmask16((1u << (end - row0)) - 1);
    const __m512i row = _mm512_add_epi32(_mm512_set1_epi32(row0), lanes);
    const __m512 y = _mm512_add_ps(_mm512_cvtepi32_ps(row), half);
    __m512 s = _mm512_mul_round_ps(_mm512_sub_ps(y, _mm512_set1_ps(line.yt)),
                                   _mm512_set1_ps(line.invDy), kNear);
    s = _mm512_min_ps(_mm512_max_ps(s, zero), one);  // max(0, s), then min(s, 1), as std::
    const __m512 x = _mm512_add_round_ps(
        _mm512_set1_ps(line.xt), _mm512_mul_round_ps(s, _mm512_set1_ps(line.dx), kNear), kNear);
    const __mmask16 inside = _mm512_mask_cmp_ps_mask(
        _mm512_mask_cmp_ps_mask(active, x, zero, _CMP_GE_OQ), x, width, _CMP_LT_OQ);
    const __m512i column = _mm512_cvttps_epi32(x);
    // b.at(x, row) = x kRows + row - first row
    const __m512i pixel =
        _mm512_add_epi32(_mm512_mullo_epi32(column, _mm512_set1_epi32(StreakBand::kRows)),
                         _mm512_sub_epi32(row, _mm512_set1_epi32(b.firstRow())));
    // One column: lane k is pixel pixel_0 + k.
    const __m512i column0 = _mm512_permutexvar_epi32(_mm512_setzero_si512(), column);
    const bool oneColumn =
        inside == active && _mm512_mask_cmpeq_epi32_mask(active, column, column0) == active;
    const int pixel0 = _mm_cvtsi128_si32(_mm512_castsi512_si128(pixel));
    const __m512 frameDepth = oneColumn ? _mm512_maskz_loadu_ps(active, depth + pixel0)
                                        : _mm512_mask_i32gather_ps(zero, inside, pixel, depth, 4);
    const __m512 z = _mm512_fmadd_ps(s, _mm512_set1_ps(line.dz), _mm512_set1_ps(line.zt));
    const __mmask16 keep = _mm512_mask_cmp_ps_mask(inside, z, frameDepth, _CMP_LT_OQ);
    const __m512 tt = _mm512_fmadd_ps(s, _mm512_set1_ps(fh), half);
    const __m512i t0 = _mm512_cvttps_epi32(tt);
    const __m512 p0 = _mm512_mask_i32gather_ps(zero, active, t0, p, 4);
    const __m512 p1 =
        _mm512_mask_i32gather_ps(zero, active, _mm512_add_epi32(t0, _mm512_set1_epi32(1)), p, 4);
    const __m512 frac = _mm512_sub_ps(tt, _mm512_cvtepi32_ps(t0));
    const __m512 a = _mm512_fmadd_ps(frac, _mm512_sub_ps(p1, p0), p0);
    const __m512 alpha = _mm512_maskz_mul_round_ps(keep, a, _mm512_set1_ps(line.coverage), kNear);
    fragments += static_cast<std::uint64_t>(__builtin_popcount(keep));
    if (oneColumn) {
      float* const q = out + 4 * static_cast<std::size_t>(pixel0);
      for (int j = 0; j < 4; ++j) {
        const __mmask16 write = kSpread[(keep >> (4 * j)) & 0xf];
        if (write == 0) continue;
        // alpha of pixels 4j .. 4j + 3, each for its 4 floats
        const __m512i spread =
            _mm512_add_epi32(_mm512_set1_epi32(4 * j), _mm512_srli_epi32(lanes, 2));
        const __m512 a4 = _mm512_permutexvar_ps(spread, alpha);
        const __m512 kept = _mm512_sub_ps(one, a4);
        const __m512 old = _mm512_maskz_loadu_ps(write, q + 16 * j);
        // L kept + c alpha (the colour's product not fused, as blendOver), T kept (+ 0 alpha)
        const __m512 blended = _mm512_fmadd_ps(old, kept, _mm512_mul_round_ps(colour, a4, kNear));
        _mm512_mask_storeu_ps(q + 16 * j, write, blended);
      }
      continue;
    }
    _mm512_store_si512(pixels, pixel);
    _mm512_store_ps(alphas, alpha);
    for (int k = 0; k < 16; ++k)
      if ((inside >> k) & 1) blendOver(out + 4 * static_cast<std::size_t>(pixels[k]), c, alphas[k]);
  }
  return fragments;
}
#endif

}  // namespace

void setUpLines(const detail::Frame& f, const std::vector<Vec3>& heads, const std::uint32_t* drops,
                int count, float lodWidth, Lines& l) {
  constexpr int kLanes = Lines::kLanes;
  alignas(64) float hx[kLanes], hy[kLanes], hz[kLanes], yHead[kLanes];
  for (int k = 0; k < kLanes; ++k) {
    const Vec3& p = heads[drops[std::min(k, count - 1)]];
    hx[k] = p.x(), hy[k] = p.y(), hz[k] = p.z();
  }
  // Plain floats, no Eigen and no branches, so that the loop vectorises; the same operations
  // in the same order as Frame::apply and halfWidthOf (Eigen sums a norm of 3 as x + (y + z)),
  // so the same bits as setting the lines up one drop at a time gave.
  const float(&m)[4][4] = f.m;
  const Vec3 dir = f.dir, eye = f.eye, right = f.right;
  const Vec4f along = f.along;
  const float halfWidth = f.halfWidth;
#pragma omp simd
  for (int k = 0; k < kLanes; ++k) {
    const float x = hx[k], y = hy[k], z = hz[k];
    // h = apply(head, 1), t = h - along
    const float hX = applyRow(m[0], x, y, z);
    const float hY = applyRow(m[1], x, y, z);
    const float hZ = applyRow(m[2], x, y, z);
    const float hW = applyRow(m[3], x, y, z);
    const float tX = hX - along.x, tY = hY - along.y, tZ = hZ - along.z, tW = hW - along.w;
    const bool between = (hW > 0) & (tW > 0) & (hZ >= 0) & (hZ <= hW) & (tZ >= 0) & (tZ <= tW);
    // halfWidthOf: halfWidth along cross(dir, eye - middle), or along the camera's right
    const float ex = eye.x() - (x - 0.5f * dir.x()), ey = eye.y() - (y - 0.5f * dir.y()),
                ez = eye.z() - (z - 0.5f * dir.z());
    float sx = dir.y() * ez - dir.z() * ey, sy = dir.z() * ex - dir.x() * ez,
          sz = dir.x() * ey - dir.y() * ex;
    const float length = std::sqrt(sx * sx + (sy * sy + sz * sz));  // as Eigen sums 3
    const bool across = length > 1e-12f;
    const float scale = halfWidth / length;
    sx = across ? sx * scale : right.x() * halfWidth;
    sy = across ? sy * scale : right.y() * halfWidth;
    sz = across ? sz * scale : right.z() * halfWidth;
    // half = apply(side, 0)
    const float halfX = m[0][0] * sx + m[0][1] * sy + m[0][2] * sz + m[0][3] * 0.0f;
    const float halfY = m[1][0] * sx + m[1][1] * sy + m[1][2] * sz + m[1][3] * 0.0f;
    const float halfW = m[3][0] * sx + m[3][1] * sy + m[3][2] * sz + m[3][3] * 0.0f;
    const float rh = 1 / hW, rt = 1 / tW;
    const float xh = hX * rh, yh = hY * rh, xt = tX * rt, yt = tY * rt;
    const float dx = xh - xt, dy = yh - yt;
    const bool steep = std::abs(dy) >= std::max(std::abs(dx), 1.0f);  // else flat or short
    // The quad's horizontal extent in a row at each end: its two long edges, 2 half apart, cut
    // by the row, (X' + dX) / (W + dW) - X' / W = (dX - x dW) / W to first order.
    const float slope = dx / dy;
    const float gapH = 2 * std::abs((halfX - xh * halfW) * rh - slope * (halfY - yh * halfW) * rh);
    const float gapT = 2 * std::abs((halfX - xt * halfW) * rt - slope * (halfY - yt * halfW) * rt);
    l.coverage[k] = std::max(gapH, gapT);
    l.ok[k] = between & steep & (l.coverage[k] < lodWidth);
    l.xt[k] = xt, l.yt[k] = yt, l.zt[k] = tZ * rt;
    l.dx[k] = dx, l.dz[k] = hZ * rh - l.zt[k], l.invDy[k] = 1 / dy;
    yHead[k] = yh;
  }
  // The rows whose centre is between the ends: floorToInt(ceil(y - 0.5), 0, height), in lanes
  // (GCC vectorises no std::ceil without -fno-trapping-math, and the loop of it took 40% of this
  // function): y clamped to [-1, height + 1] first, where the conversion to int is exact, and
  // rounded up by hand. The same rows for every finite y.
  const int rows = f.height;
  const float rowsEnd = static_cast<float>(rows) + 1;
#pragma omp simd
  for (int k = 0; k < kLanes; ++k) {
    const float lo = std::min(std::max(std::min(l.yt[k], yHead[k]) - 0.5f, -1.0f), rowsEnd);
    const float hi = std::min(std::max(std::max(l.yt[k], yHead[k]) - 0.5f, -1.0f), rowsEnd);
    const int iLo = static_cast<int>(lo), iHi = static_cast<int>(hi);  // towards zero
    const int first = iLo + (static_cast<float>(iLo) < lo ? 1 : 0);
    const int end = iHi + (static_cast<float>(iHi) < hi ? 1 : 0);
    l.first[k] = std::min(std::max(first, 0), rows);
    l.end[k] = std::min(std::max(end, 0), rows);
  }
}

std::uint64_t drawLineRows(const Line& line, int first, int end, StreakBand& b, const Vec3& c,
                           const float* profile, float fh, bool simd) {
#if defined(__AVX512F__)
  if (simd) return rowsInLanes(line, first, end, b, c, profile, fh);
#else
  (void)simd;
#endif
  return rowsOneByOne(line, first, end, b, c, profile, fh);
}

}  // namespace sph::render::rain
