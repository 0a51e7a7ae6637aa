// A particle's candidates inside its support, selected before any kernel is evaluated (the DFSPH
// factor pass, sim/solver/DfsphPairs.cpp). A cell's batch holds the candidates of 27 cells, of
// which about one in six lies within the support of a given particle at support 2 spacings; so
// the pass first keeps those with 0 < r^2 < h^2, with their offset x_i - x_j, r^2 and index bits,
// in their order, and evaluates the kernel on them alone.
//
// Data movement and one comparison, so both versions select the same candidates (up to how r^2
// rounds; tests/test_support_selection.cpp holds them to it on this machine whichever one the
// build picks): with AVX-512 each 8 lanes are compressed in a register and stored whole (the lanes
// past the count are overwritten by the next ones), as PairPacking.h does; the scalar one stores
// every candidate and advances past those inside. Either way the selection ends padded with
// zeros (r^2 = 0: outside) to a multiple of kBatchLanes, so the loop over it needs no epilogue.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define SPHSPLAT_SELECT_SUPPORT_AVX512 1
#endif

#include "sim/grid/CellBatch.h"

namespace sph::grid {

// The selected candidates: fields dx, dy, dz (x_i - x_j), r^2 and the index bits.
using SupportSelection = CandidateBatch<5>;

// Pads `out` from `count` to a multiple of kBatchLanes with zeros and sets its count.
inline std::size_t padSelection(std::size_t count, SupportSelection& out) {
  const std::size_t padded = (count + kBatchLanes - 1) / kBatchLanes * kBatchLanes;
  for (auto& f : out.field) {
    for (std::size_t k = count; k < padded; ++k) f[k] = 0.0f;
  }
  out.count = count, out.padded = padded;
  return count;
}

// Where a version writes: the selection's fields.
struct SelectionFields {
  float *dx, *dy, *dz, *r2, *id;
};
inline SelectionFields fieldsOf(SupportSelection& out) {
  return {out.field[0].data(), out.field[1].data(), out.field[2].data(), out.field[3].data(),
          out.field[4].data()};
}

// The candidates of `padded` (fields x, y, z and index bits; a multiple of kBatchLanes) within
// sqrt(h2) of (xi, yi, zi), itself left out, into `out`, which must have room for `padded`
// values. A candidate just inside the edge may still read h - r <= 0 where the kernel is evaluated
// with a reciprocal square-root estimate (-ffast-math): it stays a pair, of weight ~0.
inline std::size_t selectInsideScalar(float xi, float yi, float zi, float h2, std::size_t padded,
                                      const float* __restrict fx, const float* __restrict fy,
                                      const float* __restrict fz, const float* __restrict bits,
                                      SupportSelection& out) {
  const auto [dx, dy, dz, r2, id] = fieldsOf(out);
  std::size_t count = 0;
  for (std::size_t j = 0; j < padded; ++j) {
    const float x = xi - fx[j], y = yi - fy[j], z = zi - fz[j];
    const float d2 = x * x + y * y + z * z;
    dx[count] = x, dy[count] = y, dz[count] = z, r2[count] = d2;
    std::memcpy(&id[count], &bits[j], sizeof(float));  // bits, not a number
    count += d2 < h2 && d2 > 0.0f ? 1 : 0;
  }
  return padSelection(count, out);
}

#if SPHSPLAT_SELECT_SUPPORT_AVX512
inline std::size_t selectInsideAvx512(float xi, float yi, float zi, float h2, std::size_t padded,
                                      const float* __restrict fx, const float* __restrict fy,
                                      const float* __restrict fz, const float* __restrict bits,
                                      SupportSelection& out) {
  const auto [dx, dy, dz, r2, id] = fieldsOf(out);
  const __m256 x0 = _mm256_set1_ps(xi), y0 = _mm256_set1_ps(yi), z0 = _mm256_set1_ps(zi);
  const __m256 limit = _mm256_set1_ps(h2), zero = _mm256_setzero_ps();
  std::size_t count = 0;
  for (std::size_t j = 0; j < padded; j += 8) {
    const __m256 x = _mm256_sub_ps(x0, _mm256_loadu_ps(fx + j));
    const __m256 y = _mm256_sub_ps(y0, _mm256_loadu_ps(fy + j));
    const __m256 z = _mm256_sub_ps(z0, _mm256_loadu_ps(fz + j));
    const __m256 d2 =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(x, x), _mm256_mul_ps(y, y)), _mm256_mul_ps(z, z));
    const __mmask8 in =
        _mm256_cmp_ps_mask(d2, limit, _CMP_LT_OQ) & _mm256_cmp_ps_mask(d2, zero, _CMP_GT_OQ);
    _mm256_storeu_ps(dx + count, _mm256_maskz_compress_ps(in, x));
    _mm256_storeu_ps(dy + count, _mm256_maskz_compress_ps(in, y));
    _mm256_storeu_ps(dz + count, _mm256_maskz_compress_ps(in, z));
    _mm256_storeu_ps(r2 + count, _mm256_maskz_compress_ps(in, d2));
    const __m256i index = _mm256_castps_si256(_mm256_loadu_ps(bits + j));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(id + count),
                        _mm256_maskz_compress_epi32(in, index));
    count += static_cast<std::size_t>(__builtin_popcount(in));
  }
  return padSelection(count, out);
}
#endif

// The version the build's CPU flags allow.
inline std::size_t selectInside(float xi, float yi, float zi, float h2, std::size_t padded,
                                const float* __restrict fx, const float* __restrict fy,
                                const float* __restrict fz, const float* __restrict bits,
                                SupportSelection& out) {
#if SPHSPLAT_SELECT_SUPPORT_AVX512
  return selectInsideAvx512(xi, yi, zi, h2, padded, fx, fy, fz, bits, out);
#else
  return selectInsideScalar(xi, yi, zi, h2, padded, fx, fy, fz, bits, out);
#endif
}

}  // namespace sph::grid
