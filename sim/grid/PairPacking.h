// Packing a particle's boundary candidates before they become its wall pairs (the DFSPH factor
// pass, sim/solver/DfsphPairs.cpp; its fluid pairs are selected before the kernel instead,
// SupportSelection.h): the candidates inside the support (h - r > 0: not the padding) are copied
// from the batch `t` (fields x, y, z of V gradW, then h - r) with their index bits to the arrays
// of `to`, in their order, and the count returned.
//
// `padded` candidates (a multiple of kBatchLanes, the batch's arrays cache-line aligned); the
// arrays have room for `padded` values. Data movement only, so both versions store the same pairs
// (tests/test_pair_packing.cpp holds them to it on this machine whichever one the build picks):
// with AVX-512 each 8 lanes are compressed in a register and stored whole (the lanes past the
// count are overwritten by the next particle's pairs), which took this loop from 42% to ~10% of
// the pass (docs/notes/2026-11-26-dfsph-peer-dam-break.md, "A cheaper density-and-factor pass");
// the scalar one stores every lane and advances past those inside.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define SPHSPLAT_PACK_PAIRS_AVX512 1
#endif

#include "sim/grid/CellBatch.h"

namespace sph::grid {

struct PairRow {
  std::uint32_t* __restrict index;
  float* __restrict gx;
  float* __restrict gy;
  float* __restrict gz;
  float* __restrict hr;
};

inline std::uint32_t packPairsScalar(std::size_t padded, const float* __restrict bits,
                                     const CandidateBatch<4>& t, PairRow to) {
  const float* __restrict tx = t.field[0].data();
  const float* __restrict ty = t.field[1].data();
  const float* __restrict tz = t.field[2].data();
  const float* __restrict th = t.field[3].data();
  std::uint32_t count = 0;
  for (std::size_t j = 0; j < padded; ++j) {
    std::memcpy(&to.index[count], &bits[j], sizeof(std::uint32_t));
    to.gx[count] = tx[j], to.gy[count] = ty[j], to.gz[count] = tz[j], to.hr[count] = th[j];
    count += th[j] > 0.0f ? 1u : 0u;
  }
  return count;
}

#if SPHSPLAT_PACK_PAIRS_AVX512
inline std::uint32_t packPairsAvx512(std::size_t padded, const float* __restrict bits,
                                     const CandidateBatch<4>& t, PairRow to) {
  const float* __restrict tx = t.field[0].data();
  const float* __restrict ty = t.field[1].data();
  const float* __restrict tz = t.field[2].data();
  const float* __restrict th = t.field[3].data();
  std::uint32_t count = 0;
  for (std::size_t j = 0; j < padded; j += 8) {
    const __m256 hr = _mm256_load_ps(th + j);
    const __mmask8 in = _mm256_cmp_ps_mask(hr, _mm256_setzero_ps(), _CMP_GT_OQ);
    const __m256i index = _mm256_castps_si256(_mm256_loadu_ps(bits + j));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(to.index + count),
                        _mm256_maskz_compress_epi32(in, index));
    _mm256_storeu_ps(to.gx + count, _mm256_maskz_compress_ps(in, _mm256_load_ps(tx + j)));
    _mm256_storeu_ps(to.gy + count, _mm256_maskz_compress_ps(in, _mm256_load_ps(ty + j)));
    _mm256_storeu_ps(to.gz + count, _mm256_maskz_compress_ps(in, _mm256_load_ps(tz + j)));
    _mm256_storeu_ps(to.hr + count, _mm256_maskz_compress_ps(in, hr));
    count += static_cast<std::uint32_t>(__builtin_popcount(in));
  }
  return count;
}
#endif

// The version the build's CPU flags allow.
inline std::uint32_t packPairs(std::size_t padded, const float* __restrict bits,
                               const CandidateBatch<4>& t, PairRow to) {
#if SPHSPLAT_PACK_PAIRS_AVX512
  return packPairsAvx512(padded, bits, t, to);
#else
  return packPairsScalar(padded, bits, t, to);
#endif
}

}  // namespace sph::grid
