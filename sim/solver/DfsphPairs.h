// DFSPH's stored fluid pairs (StepScratch::pairs, sim/grid/PairStore.h): the per-step neighbour
// list that computeDfsphDensityAndFactor() builds (sim/solver/DfsphPairs.cpp) and every other DFSPH
// pass walks (sim/solver/Dfsph.cpp, DfsphViscosity.cpp). Internal to those files, which are built
// with -ffast-math.
#pragma once

#include <cstdint>

#include "sim/grid/CellBatch.h"
#include "sim/Parallel.h"
#include "sim/solver/StepContext.h"

namespace sph::solver {

// V gradW_spiky(x_i - x_j) = gradientScale (h - r)^2 / r (x_i - x_j): the exact gradient of the
// normalised density sum over rho0 (SphPasses.cpp, computeDensity()).
inline float dfsphGradientScale(const StepContext& c) {
  return c.derived.kernels.spikyGradFactor * c.derived.mass * c.derived.densityNormalisation /
         c.solver.restDensity;
}

// One particle's pairs: `count` neighbours j (index), V_j gradW_ij (gx, gy, gz; 1/m) and
// h - r_ij (hr; m), contiguous.
struct PairSpan {
  const std::uint32_t* index;
  const float *gx, *gy, *gz, *hr;
  std::uint32_t count;
};

// forEachParticlePairs() calls body(i, pairs) for every fluid particle, in parallel by rows of
// cells, with its pairs of this step. The passes over them are scalar loops (sim/solver/
// CMakeLists.txt says why) that sum each particle's pairs in their stored order, so the sums keep
// their bits wherever a row lands in memory, whatever the thread count, and on K processes with
// slabs across x, where a row holds only the rank's part (tests/test_mpi.cpp, MpiDfsph).
template <bool kWalls, class Body>
void forEachParticlePairRows(const StepContext& c, Body& body) {
  const StepScratch& s = c.scratch;
  parallelForDynamic(rowCount(c.grid), 4, [&](std::size_t row) {
    const auto [begin, end] = rowRange(c.grid, row);
    const grid::PairStore::Row r = s.pairs.row(row);
    std::size_t at = 0;
    [[maybe_unused]] grid::PairStore::Row w;
    [[maybe_unused]] std::size_t atWall = 0;
    if constexpr (kWalls) w = s.wallPairs.row(row);
    for (std::uint32_t i = begin; i < end; ++i) {
      const std::uint32_t count = s.pairCount[i];
      const PairSpan pairs{r.index + at, r.gx + at, r.gy + at, r.gz + at, r.hr + at, count};
      at += count;
      if constexpr (kWalls) {
        const std::uint32_t walls = s.wallPairCount[i];
        body(i, pairs,
             PairSpan{w.index + atWall, w.gx + atWall, w.gy + atWall, w.gz + atWall, w.hr + atWall,
                      walls});
        atWall += walls;
      } else {
        body(i, pairs);
      }
    }
  });
}

template <class Body>
void forEachParticlePairs(const StepContext& c, Body&& body) {
  forEachParticlePairRows<false>(c, body);
}

// The same with each particle's wall pairs too (StepScratch::wallPairs, DfsphWalls.cpp):
// body(i, pairs, wallPairs).
template <class Body>
void forEachParticlePairsAndWalls(const StepContext& c, Body&& body) {
  forEachParticlePairRows<true>(c, body);
}

}  // namespace sph::solver
