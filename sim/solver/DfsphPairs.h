// DFSPH's stored fluid pairs (StepScratch::pairs, sim/grid/PairStore.h): the per-step neighbour
// list that computeDfsphDensityAndFactor() builds (sim/solver/DfsphPairs.cpp) and every other DFSPH
// pass walks (sim/solver/Dfsph.cpp, DfsphViscosity.cpp). Internal to those files, which are built
// with -ffast-math.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>

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

// Monaghan's viscosity keeps r^2 + kMonaghanSoftening h^2 from 0 (DfsphViscosity.cpp).
constexpr float kMonaghanSoftening = 0.01f;

// One particle's pairs: `count` records (the neighbour j and V_j gradW_ij, 1/m) and each pair's
// viscosity weight, contiguous: h - r_ij (m), or with Monaghan's form its own factor
// (DfsphPairs.cpp, fluidPairs()); a wall pair's is h - r_ib.
struct PairSpan {
  const grid::PairRecord* pair;
  const float* weight;
  std::uint32_t count;
};

// Four floats in one register (GCC's and Clang's vector extension, on any target): a pair's record
// (lane 0 its index's bits) or a particle's packed velocity (lane 0 zero). A pass sums a pair as
// one product of such registers, the three components in lanes 1-3 (lane 0 is never read): two
// loads a pair where three scalar products took seven, and no gather (sim/solver/CMakeLists.txt
// says why the passes are not vectorised across pairs).
typedef float Float4 __attribute__((vector_size(16)));

inline Float4 loadRecord(const grid::PairRecord& r) {
  Float4 v;
  std::memcpy(&v, &r, sizeof v);
  return v;
}

// Each particle's velocity as {0, vx, vy, vz} in StepScratch::packedVelocity, for the passes that
// read their neighbours' velocities.
inline const Float4* packVelocities(StepContext& c) {
  const Particles& f = c.fluid;
  std::vector<std::array<float, 4>>& v = c.scratch.packedVelocity;
  v.resize(f.size());
  parallelFor(f.size(), [&](std::size_t i) { v[i] = {0.0f, f.vx[i], f.vy[i], f.vz[i]}; });
  static_assert(sizeof(v[0]) == sizeof(Float4));
  return reinterpret_cast<const Float4*>(v.data());
}

// sum over the pairs `p` of weight(j) * V_j gradW_ij, the weight a float or a Float4 (lanes 1-3 of
// the result). Two running sums, even and odd pairs, added at the end: one sum would wait on the
// last addition at every pair (a loop bound by the adder's latency, not by its loads).
template <class Weight>
Float4 weightedPairSum(const PairSpan& p, Weight&& weight) {
  Float4 even = {0, 0, 0, 0}, odd = {0, 0, 0, 0};
  std::uint32_t q = 0;
  for (; q + 1 < p.count; q += 2) {
    even += weight(p.pair[q].index) * loadRecord(p.pair[q]);
    odd += weight(p.pair[q + 1].index) * loadRecord(p.pair[q + 1]);
  }
  if (q < p.count) even += weight(p.pair[q].index) * loadRecord(p.pair[q]);
  return even + odd;
}

// forEachParticlePairs() calls body(i, pairs) for every fluid particle, in parallel by rows of
// cells, with its pairs of this step. The passes over them sum each particle's pairs in their
// stored order (weightedPairSum()), so the sums keep their bits wherever a row lands in memory,
// whatever the thread count, and on K processes with slabs across x, where a row holds only the
// rank's part (tests/test_mpi.cpp, MpiDfsph).
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
      const PairSpan pairs{r.pair + at, r.weight + at, count};
      at += count;
      if constexpr (kWalls) {
        const std::uint32_t walls = s.wallPairCount[i];
        body(i, pairs, PairSpan{w.pair + atWall, w.weight + atWall, walls});
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
