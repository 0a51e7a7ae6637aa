// Cell-batched neighbour loops. Particles are sorted by cell, and every particle of a cell has the
// same 27 candidate cells; so the hot passes walk the grid cell by cell, copy the candidates'
// fields once per cell into contiguous per-thread arrays padded to the vector width, and run one
// branch-free `omp simd` loop per particle over them. Compared with looping over the 9 ranges
// directly this removes the vector epilogues of short ranges (most of the time at support 2
// spacings, where a range holds ~24 particles).
//
// Each particle still sums its own neighbours in a fixed order (the cell order), so results do
// not depend on the thread count.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define SPHSPLAT_APPEND_NEAR_AVX512 1
#endif

#include "sim/Assert.h"
#include "sim/grid/NeighbourGrid.h"
#include "sim/Parallel.h"

namespace sph::grid {

// Batch storage starts on a 64-byte boundary: vectorised loops peel a number of scalar
// iterations that depends on the start address, and that would change the order of the simd
// reductions (and so the last bits of the sums) with the heap layout of each thread.
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = (n * sizeof(T) + 63) / 64 * 64;
    void* p = std::aligned_alloc(64, bytes);
    if (!p) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const {
    return true;
  }
  template <class U>
  bool operator!=(const CacheLineAllocator<U>&) const {
    return false;
  }
};

// Padding lanes hold a point this far away: outside any support, and its square stays finite.
constexpr float kFarAway = 1e15f;
constexpr std::size_t kBatchLanes = 16;  // a multiple of every SIMD width we build for

// The candidates of [begin, end) (fields `src`, x, y, z first) within sqrt(reach2) of the box
// [lo, hi], copied in their order to `to`, which has room for end - begin + 8 values; returns how
// many. Data movement and one distance test: both versions keep the same candidates, but for one
// whose distance rounds to the bound itself (tests/test_append_near.cpp holds them to it on this
// machine whichever one the build picks).
//
// Without a branch: the scalar one copies every candidate and advances past those kept, as a
// quarter of them mispredicted (docs/notes/2026-11-26-dfsph-peer-dam-break.md, "A cheaper
// density-and-factor pass"). With AVX-512 each 8 are tested in a register and compressed: the
// loop had become 9% of the DFSPH step, and DFSPH's factor pass went from 23 to 17 ms a step
// (docs/notes/2026-11-30-dfsph-step-cost.md, "The candidates compressed").
template <int N>
std::size_t appendNearScalar(const std::array<const float*, N>& src, std::uint32_t begin,
                             std::uint32_t end, const float lo[3], const float hi[3], float reach2,
                             const std::array<float*, N>& to) {
  std::size_t at = 0;
  for (std::uint32_t q = begin; q < end; ++q) {
    float d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const float v = src[a][q];
      const float d = std::max(std::max(lo[a] - v, v - hi[a]), 0.0f);
      d2 += d * d;
    }
    for (int f = 0; f < N; ++f) to[f][at] = src[f][q];
    at += d2 >= reach2 ? 0 : 1;  // the same test as a branch would make, NaN included
  }
  return at;
}

#if SPHSPLAT_APPEND_NEAR_AVX512
template <int N>
std::size_t appendNearAvx512(const std::array<const float*, N>& src, std::uint32_t begin,
                             std::uint32_t end, const float lo[3], const float hi[3], float reach2,
                             const std::array<float*, N>& to) {
  const __m256 zero = _mm256_setzero_ps(), bound = _mm256_set1_ps(reach2);
  std::size_t at = 0;
  for (std::uint32_t q = begin; q < end; q += 8) {
    const __mmask8 live =
        end - q >= 8 ? __mmask8{0xFF} : static_cast<__mmask8>((1u << (end - q)) - 1);
    __m256 value[N];
    for (int f = 0; f < N; ++f) value[f] = _mm256_maskz_loadu_ps(live, src[f] + q);
    __m256 d2 = zero;
    for (int a = 0; a < 3; ++a) {
      // maxps returns its second operand when either is NaN: a NaN coordinate stays NaN here, as
      // in the scalar version, and the candidate is kept.
      const __m256 outside = _mm256_max_ps(_mm256_sub_ps(value[a], _mm256_set1_ps(hi[a])),
                                           _mm256_sub_ps(_mm256_set1_ps(lo[a]), value[a]));
      const __m256 d = _mm256_max_ps(zero, outside);
      d2 = _mm256_add_ps(d2, _mm256_mul_ps(d, d));
    }
    // Kept: not d2 >= reach2 (NaN kept, as the scalar test does), among the live lanes.
    const __mmask8 keep = _mm256_mask_cmp_ps_mask(live, d2, bound, _CMP_NGE_UQ);
    for (int f = 0; f < N; ++f)
      _mm256_storeu_ps(to[f] + at, _mm256_maskz_compress_ps(keep, value[f]));
    at += static_cast<std::size_t>(__builtin_popcount(keep));
  }
  return at;
}
#endif

// The version the build's CPU flags allow.
template <int N>
std::size_t appendNearCandidates(const std::array<const float*, N>& src, std::uint32_t begin,
                                 std::uint32_t end, const float lo[3], const float hi[3],
                                 float reach2, const std::array<float*, N>& to) {
#if SPHSPLAT_APPEND_NEAR_AVX512
  return appendNearAvx512<N>(src, begin, end, lo, hi, reach2, to);
#else
  return appendNearScalar<N>(src, begin, end, lo, hi, reach2, to);
#endif
}

template <int N>
struct CandidateBatch {
  std::array<std::vector<float, CacheLineAllocator<float>>, N> field;  // field[0..2]: x, y, z
  std::size_t count = 0;                                               // real candidates
  std::size_t padded = 0;  // count rounded up to kBatchLanes

  void clear() { count = 0; }
  // Room for n values in every field (their contents unspecified).
  void resize(std::size_t n) { reserve(n); }
  // Appends those of [begin, end) whose position lies within sqrt(reach2) of the box [lo, hi]:
  // the candidates some particle of the cell can actually reach. At support 2 spacings this drops
  // the far corners of the 27-cell block, about a quarter of it (appendNearCandidates() below).
  void appendNear(const std::array<const float*, N>& src, std::uint32_t begin, std::uint32_t end,
                  const float lo[3], const float hi[3], float reach2) {
    reserve(count + (end - begin) + kBatchLanes);
    std::array<float*, N> to;
    for (int f = 0; f < N; ++f) to[f] = field[f].data() + count;
    count += appendNearCandidates<N>(src, begin, end, lo, hi, reach2, to);
  }
  // Pads to a multiple of kBatchLanes: positions far away, every other field 0.
  void pad() {
    padded = (count + kBatchLanes - 1) / kBatchLanes * kBatchLanes;
    reserve(padded);
    for (int f = 0; f < N; ++f) {
      for (std::size_t k = count; k < padded; ++k) field[f][k] = f < 3 ? kFarAway : 0.0f;
    }
  }

 private:
  void reserve(std::size_t n) {
    if (field[0].size() >= n) return;
    for (auto& v : field) v.resize(n * 2);
  }
};

// The rows of `grid`'s cells (along x; dims y x z of them) and the particles of one: a contiguous
// range, as the particles are sorted by cell.
inline std::size_t rowCount(const NeighbourGrid& grid) {
  const CellCoord d = grid.dims();
  return grid.cellCount() == 0 ? 0 : static_cast<std::size_t>(d[1]) * d[2];
}
inline std::pair<std::uint32_t, std::uint32_t> rowRange(const NeighbourGrid& grid,
                                                        std::size_t row) {
  const CellCoord d = grid.dims();
  const int j = static_cast<int>(row % d[1]), k = static_cast<int>(row / d[1]);
  return {grid.cellBegin(grid.localIndex(0, j, k)), grid.cellEnd(grid.localIndex(d[0] - 1, j, k))};
}

// Calls body(begin, end, fluidBatch, boundaryBatch) once for every non-empty cell of `grid`,
// in parallel (or body(row, begin, end, ...) with the row of cells, rowRange(), it belongs to;
// one row's cells are visited in order by one thread), where [begin, end) are the cell's particles
// and the batches hold the candidates of the 27 surrounding cells: from `grid` with the N fluid
// fields, and from `boundaryGrid` (every boundary cell within `reach` of the cell, i.e. the same 27
// cells when both grids share the cell size) with the M boundary fields. `reach` must be at least
// the support radius.
template <int N, int M, class Body>
void forEachCellWithCandidates(const NeighbourGrid& grid, const std::array<const float*, N>& fluid,
                               const NeighbourGrid& boundaryGrid,
                               const std::array<const float*, M>& boundary, float reach,
                               Body&& body) {
  const CellCoord dims = grid.dims(), origin = grid.origin();
  const std::size_t rows = static_cast<std::size_t>(dims[1]) * dims[2];
  if (grid.cellCount() == 0) return;
  const int threads = threadCount();
  std::vector<CandidateBatch<N>> fluidBatches(threads);
  std::vector<CandidateBatch<M>> boundaryBatches(threads);
  const bool sameLattice = boundaryGrid.cellSize() == grid.cellSize();
  reach *= 1.0001f;  // generous: an extra candidate costs time, a missing one correctness
  const float reach2 = reach * reach;
  parallelForDynamic(rows, 4, [&](std::size_t row) {
    CandidateBatch<N>& fb = fluidBatches[threadIndex()];
    CandidateBatch<M>& bb = boundaryBatches[threadIndex()];
    const int j = static_cast<int>(row % dims[1]), k = static_cast<int>(row / dims[1]);
    for (int i = 0; i < dims[0]; ++i) {
      const std::size_t cell = grid.localIndex(i, j, k);
      const std::uint32_t begin = grid.cellBegin(cell), end = grid.cellEnd(cell);
      if (begin == end) continue;
      const CellCoord g = {origin[0] + i, origin[1] + j, origin[2] + k};
      // The cell's own particles bound the box the candidates are culled against (tighter than
      // the cell, and immune to the rounding of cell borders).
      float lo[3] = {fluid[0][begin], fluid[1][begin], fluid[2][begin]},
            hi[3] = {lo[0], lo[1], lo[2]};
      for (std::uint32_t q = begin + 1; q < end; ++q) {
        for (int a = 0; a < 3; ++a)
          lo[a] = std::min(lo[a], fluid[a][q]), hi[a] = std::max(hi[a], fluid[a][q]);
      }
      fb.clear();
      grid.forEachNeighbourRange(
          g, [&](std::uint32_t b, std::uint32_t e) { fb.appendNear(fluid, b, e, lo, hi, reach2); });
      fb.pad();
      bb.clear();
      auto appendBoundary = [&](std::uint32_t b, std::uint32_t e) {
        bb.appendNear(boundary, b, e, lo, hi, reach2);
      };
      if (sameLattice) {
        boundaryGrid.forEachNeighbourRange(g, appendBoundary);
      } else {  // one grid grew its cells: take every boundary cell the support can reach
        const float blo[3] = {lo[0] - reach, lo[1] - reach, lo[2] - reach};
        const float bhi[3] = {hi[0] + reach, hi[1] + reach, hi[2] + reach};
        boundaryGrid.forEachRangeInBox(blo, bhi, appendBoundary);
      }
      bb.pad();
      // Every particle of the cell is its own neighbour: the batch must hold at least them.
      validate("collecting a cell's neighbour candidates", [&] {
        return fb.count >= end - begin
                   ? std::string()
                   : "cell (" + std::to_string(g[0]) + ", " + std::to_string(g[1]) + ", " +
                         std::to_string(g[2]) + ") has " + std::to_string(end - begin) +
                         " particles but " + std::to_string(fb.count) + " candidates";
      });
      if constexpr (std::is_invocable_v<Body&, std::size_t, std::uint32_t, std::uint32_t,
                                        const CandidateBatch<N>&, const CandidateBatch<M>&>) {
        body(row, begin, end, fb, bb);
      } else {
        body(begin, end, fb, bb);
      }
    }
  });
}

}  // namespace sph::grid
