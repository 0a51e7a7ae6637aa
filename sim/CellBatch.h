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

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/NeighbourGrid.h"
#include "sim/Parallel.h"

namespace sph {

// Padding lanes hold a point this far away: outside any support, and its square stays finite.
constexpr float kFarAway = 1e15f;
constexpr std::size_t kBatchLanes = 16;  // a multiple of every SIMD width we build for

template <int N>
struct CandidateBatch {
  std::array<std::vector<float>, N> field;  // field[0..2] are x, y, z
  std::size_t count = 0;    // real candidates
  std::size_t padded = 0;   // count rounded up to kBatchLanes

  void clear() { count = 0; }
  // Appends [begin, end) of the source arrays.
  void append(const std::array<const float*, N>& src, std::uint32_t begin, std::uint32_t end) {
    const std::size_t n = end - begin;
    reserve(count + n + kBatchLanes);
    for (int f = 0; f < N; ++f) {
      const float* s = src[f] + begin;
      float* d = field[f].data() + count;
      for (std::size_t k = 0; k < n; ++k) d[k] = s[k];
    }
    count += n;
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

// Calls body(begin, end, fluidBatch, boundaryBatch) once for every non-empty cell of `grid`,
// in parallel, where [begin, end) are the cell's particles and the batches hold the candidates
// of the 27 surrounding cells: from `grid` with the N fluid fields, and from `boundaryGrid`
// (every boundary cell within `reach` of the cell, i.e. the same 27 cells when both grids share
// the cell size) with the M boundary fields. `reach` must be at least the support radius.
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
  const float c = grid.cellSize();
  const bool sameLattice = boundaryGrid.cellSize() == c;
  reach *= 1.001f;  // generous: an extra cell costs time, a missing one correctness
  parallelForDynamic(rows, 4, [&](std::size_t row) {
    CandidateBatch<N>& fb = fluidBatches[threadIndex()];
    CandidateBatch<M>& bb = boundaryBatches[threadIndex()];
    const int j = static_cast<int>(row % dims[1]), k = static_cast<int>(row / dims[1]);
    for (int i = 0; i < dims[0]; ++i) {
      const std::size_t cell = grid.localIndex(i, j, k);
      const std::uint32_t begin = grid.cellBegin(cell), end = grid.cellEnd(cell);
      if (begin == end) continue;
      const CellCoord g = {origin[0] + i, origin[1] + j, origin[2] + k};
      fb.clear();
      grid.forEachNeighbourRange(g, [&](std::uint32_t b, std::uint32_t e) { fb.append(fluid, b, e); });
      fb.pad();
      bb.clear();
      auto appendBoundary = [&](std::uint32_t b, std::uint32_t e) { bb.append(boundary, b, e); };
      if (sameLattice) {
        boundaryGrid.forEachNeighbourRange(g, appendBoundary);
      } else {  // one grid grew its cells: take every boundary cell the support can reach
        const float lo[3] = {g[0] * c - reach, g[1] * c - reach, g[2] * c - reach};
        const float hi[3] = {(g[0] + 1) * c + reach, (g[1] + 1) * c + reach, (g[2] + 1) * c + reach};
        boundaryGrid.forEachRangeInBox(lo, hi, appendBoundary);
      }
      bb.pad();
      body(begin, end, fb, bb);
    }
  });
}

}  // namespace sph
