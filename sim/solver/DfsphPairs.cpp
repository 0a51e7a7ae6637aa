// computeDfsphDensityAndFactor(), the DFSPH step's one neighbour search: the summation density
// (seed 003, eq. (1), spiky kernel), Bender & Koschier's per-particle factor (2017, eq. 9;
// Dfsph.cpp gives the notation) and the fluid pairs with V_j gradW_ij and h - r_ij, stored for the
// passes after it (StepScratch::pairs). One pass where WCSPH's density pass and a separate factor
// pass each searched the neighbours.
//
// Built with -ffast-math like SphPasses.cpp (sim/solver/CMakeLists.txt), under the same rules: the
// search runs in cell-range loops of forEachCellWithCandidates, the same whatever the thread
// count.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "sim/solver/DfsphPairs.h"
#include "sim/grid/PairPacking.h"
#include "sim/grid/SupportSelection.h"
#include "sim/solver/SphPasses.h"

namespace sph::solver {
namespace {

// The same 32 bits as another type (std::bit_cast, C++20).
template <class To, class From>
To bitsAs(From from) {
  static_assert(sizeof(To) == sizeof(From));
  To to;
  std::memcpy(&to, &from, sizeof(to));
  return to;
}

// sum_j |V gradW_ij|^2 for a particle inside the rest lattice (where G_i = 0): the scale of
// alpha's denominator for a full neighbourhood.
float latticeDenominator(const StepContext& c) {
  const float dx = c.solver.spacing, h = c.derived.h, g = dfsphGradientScale(c);
  const int reach = static_cast<int>(std::ceil(h / dx));
  double sum = 0;
  for (int i = -reach; i <= reach; ++i)
    for (int j = -reach; j <= reach; ++j)
      for (int k = -reach; k <= reach; ++k) {
        const double r = dx * std::sqrt(static_cast<double>(i * i + j * j + k * k));
        if (r <= 0 || r >= h) continue;
        const double w = g * (h - r) * (h - r);  // |V gradW| = |g| (h - r)^2
        sum += w * w;
      }
  return static_cast<float>(sum);
}

// A particle's sums over its candidates inside the support (`in`, grid/SupportSelection.h; the
// padding lanes add 0), and each one's record (index bits and V gradW) and viscosity weight into
// the row `to`, which must have room for in.padded pairs: h - r for the Laplacian form, or with
// kMonaghan r / ((h - r)^2 (r^2 + softening)), the factor Monaghan's form puts on v_ij . R_j
// (DfsphViscosity.cpp), 0 for a pair stored at the support's edge. Divided here, vectorised, where
// the viscosity pass would divide once a pair in a scalar loop (twice the Laplacian's time). A
// plain function with unaliased pointers: as a loop inside the pass's lambda, GCC 12 left it
// scalar.
struct FluidSums {
  float gx, gy, gz, squares, cubes, moment;
};
template <bool kMonaghan>
FluidSums fluidPairs(const grid::SupportSelection& in, SpikyPairShape spiky, float g,
                     float softening, const grid::PairStore::Row& to) {
  const float* __restrict ox = in.field[0].data();
  const float* __restrict oy = in.field[1].data();
  const float* __restrict oz = in.field[2].data();
  const float* __restrict d2 = in.field[3].data();
  const float* __restrict bits = in.field[4].data();
  static_assert(sizeof(grid::PairRecord) == 4 * sizeof(float));
  float* __restrict record = reinterpret_cast<float*>(to.pair);
  float* __restrict th = to.weight;
  float gx = 0, gy = 0, gz = 0, squares = 0, cubes = 0, moment = 0;
#pragma omp simd reduction(+ : gx, gy, gz, squares, cubes, moment)
  for (std::size_t j = 0; j < in.padded; ++j) {
    const float dx = ox[j], dy = oy[j], dz = oz[j], r2 = d2[j];
    const float invR = spiky.inverseDistance(r2);
    const float hr = spiky.hMinusR(r2, invR);
    const float wj = hr * hr * invR;
    if constexpr (kMonaghan) {
      const float r = spiky.h - hr, denominator = hr * hr * (r * r + softening);
      th[j] = denominator > 0 ? r / denominator : 0.0f;
    } else {
      th[j] = hr;
    }
    record[4 * j] = bits[j];
    record[4 * j + 1] = g * wj * dx, record[4 * j + 2] = g * wj * dy,
                   record[4 * j + 3] = g * wj * dz;
    gx += wj * dx, gy += wj * dy, gz += wj * dz;
    squares += wj * wj * r2;
    cubes += hr * hr * hr;
    moment += wj * r2;  // (h - r)^2 r
  }
  return {gx, gy, gz, squares, cubes, moment};
}

// A particle's wall pairs as packPairs() leaves them, field by field (room for `padded`
// candidates: it writes whole batches of lanes), and storeRecords(), which makes them the row's
// records in whole blocks of 8 (no remainder loop): the fields must be readable, and the row have
// room, up to recordsWritten().
struct PackedWallPairs {
  std::vector<std::uint32_t> index;
  std::vector<float> gx, gy, gz, hr;
  void resize(std::size_t padded) {
    if (index.size() >= padded) return;
    index.resize(padded), gx.resize(padded), gy.resize(padded), gz.resize(padded);
    hr.resize(padded);
  }
  static constexpr std::size_t kBlock = 8;
  static std::size_t recordsWritten(std::size_t count) {
    return (count + kBlock - 1) / kBlock * kBlock;
  }
  void storeRecords(std::size_t count, const grid::PairStore::Row& to) const {
    const float* __restrict bits = reinterpret_cast<const float*>(index.data());
    const float* __restrict x = gx.data(), * __restrict y = gy.data(), * __restrict z = gz.data();
    const float* __restrict h = hr.data();
    float* __restrict record = reinterpret_cast<float*>(to.pair);
    for (std::size_t q0 = 0; q0 < count; q0 += kBlock) {
      for (std::size_t q = q0; q < q0 + kBlock; ++q) {
        record[4 * q] = bits[q], record[4 * q + 1] = x[q], record[4 * q + 2] = y[q];
        record[4 * q + 3] = z[q], to.weight[q] = h[q];
      }
    }
  }
};

struct BoundarySums {
  float gx, gy, gz, cubes, weight, moment;
};
template <bool kStorePairs>
BoundarySums boundaryCandidates(float xi, float yi, float zi, const grid::CandidateBatch<4>& bb,
                                SpikyPairShape spiky, float g, grid::CandidateBatch<4>& out) {
  const float* __restrict bxs = bb.field[0].data();
  const float* __restrict bys = bb.field[1].data();
  const float* __restrict bzs = bb.field[2].data();
  float* __restrict tx = out.field[0].data();
  float* __restrict ty = out.field[1].data();
  float* __restrict tz = out.field[2].data();
  float* __restrict th = out.field[3].data();
  float gx = 0, gy = 0, gz = 0, cubes = 0, weight = 0, moment = 0;
#pragma omp simd reduction(+ : gx, gy, gz, cubes, weight, moment)
  for (std::size_t j = 0; j < bb.padded; ++j) {
    const float dx = xi - bxs[j], dy = yi - bys[j], dz = zi - bzs[j];
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float invR = spiky.inverseDistance(r2);
    const float hr = spiky.hMinusR(r2, invR);
    const float wb = hr * hr * invR;
    gx += wb * dx, gy += wb * dy, gz += wb * dz;
    cubes += hr * hr * hr;
    weight += hr;
    moment += wb * r2;
    if constexpr (kStorePairs) {
      th[j] = hr;
      tx[j] = g * wb * dx, ty[j] = g * wb * dy, tz[j] = g * wb * dz;
    }
  }
  return {gx, gy, gz, cubes, weight, moment};
}

}  // namespace

void computeDfsphDensityAndFactor(StepContext& c) {
  Particles& f = c.fluid;
  const BoundaryParticles& b = c.boundary.particles();
  StepScratch& s = c.scratch;
  const std::size_t n = f.size();
  s.gradientSumX.resize(n), s.gradientSumY.resize(n), s.gradientSumZ.resize(n);
  s.factor.resize(n);
  s.pairCount.resize(n);
  s.inverseDensity.resize(n);
  s.wallWeight.resize(n);
  s.gradientMoment.resize(n);
  if (s.indexBits.size() < n) {  // the bits of i: unchanged by the sort, so set once
    const std::size_t from = s.indexBits.size();
    s.indexBits.resize(n);
    for (std::size_t i = from; i < n; ++i)
      s.indexBits[i] = bitsAs<float>(static_cast<std::uint32_t>(i));
  }
  s.pairs.begin(rowCount(c.grid), threadCount());
  const bool wallPairs = c.solver.wallPressure == scene::WallPressure::Extrapolated;
  std::vector<float>& boundaryBits = c.walls.indexBits;
  if (boundaryBits.size() != b.size()) {  // the boundary never changes: set once
    boundaryBits.resize(b.size());
    for (std::size_t q = 0; q < b.size(); ++q)
      boundaryBits[q] = bitsAs<float>(static_cast<std::uint32_t>(q));
  }
  if (wallPairs) {
    s.wallPairCount.resize(n);
    s.wallPairs.begin(rowCount(c.grid), threadCount());
  }
  const float h = c.derived.h;
  const SpikyPairShape spiky{h, h * h};
  const bool monaghan = c.solver.viscosityForm == scene::ViscosityForm::Monaghan;
  const float softening = kMonaghanSoftening * h * h;
  const float g = dfsphGradientScale(c);
  // rho = densityScale sum (h - r)^3, the particle itself (r = 0, which the pair shape leaves
  // out) included: SpikyShape with the spiky factor (the scene loader requires the spiky density
  // kernel with DFSPH).
  const float densityScale =
      c.derived.kernels.spikyFactor * c.derived.mass * c.derived.densityNormalisation;
  const float self = h * h * h;
  // A floor under alpha's denominator: a particle with a sparse neighbourhood (a drop touching a
  // wall at the edge of the support) has a tiny one, and its stiffness, acting on its few
  // neighbours through their gradients rather than its own, blew up runs. A quarter of the full
  // neighbourhood's value leaves every particle with half a neighbourhood or more (the free
  // surface) untouched and under-corrects only spray.
  const float floor = 0.25f * latticeDenominator(c);
  const float jacobiStep = c.derived.jacobiStep;  // 1 up to a support of 2 spacings
  // The gradient moment K_i (SphPasses.cpp, computeDensity()): not used by the solvers, but it
  // turns their stiffness into a pressure (solveDensity()) as WCSPH's force is scaled.
  const float momentScale = -c.derived.kernels.spikyGradFactor * c.derived.mass /
                            c.solver.restDensity / 3;
  // Per thread: the candidates inside the support (whose records fluidPairs() writes into the
  // row); the boundary candidates' V gradW_ib and h - r (0 outside the support), and those inside
  // packed, before they become the row's wall records.
  std::vector<grid::SupportSelection> inside(threadCount());
  std::vector<grid::CandidateBatch<4>> wallGradients(threadCount());
  std::vector<PackedWallPairs> wallPacking(threadCount());
  grid::forEachCellWithCandidates<4, 4>(
      c.grid, {f.x.data(), f.y.data(), f.z.data(), s.indexBits.data()}, c.boundary.grid(),
      {b.x.data(), b.y.data(), b.z.data(), boundaryBits.data()}, h,
      [&](std::size_t row, std::uint32_t begin, std::uint32_t end,
          const grid::CandidateBatch<4>& fb, const grid::CandidateBatch<4>& bb) {
        const int thread = threadIndex();
        grid::SupportSelection& in = inside[thread];
        in.resize(fb.padded);
        grid::CandidateBatch<4>& tw = wallGradients[thread];
        if (wallPairs) tw.resize(bb.padded);
        const float* fx = fb.field[0].data();
        const float* fy = fb.field[1].data();
        const float* fz = fb.field[2].data();
        const float* bits = fb.field[3].data();
        for (std::uint32_t i = begin; i < end; ++i) {
          const float xi = f.x[i], yi = f.y[i], zi = f.z[i];
          // The pairs: the candidates inside the support.
          const std::size_t count =
              grid::selectInside(xi, yi, zi, spiky.h2, fb.padded, fx, fy, fz, bits, in);
          const grid::PairStore::Row to = s.pairs.room(row, thread, in.padded);
          const FluidSums sums = monaghan ? fluidPairs<true>(in, spiky, g, softening, to)
                                          : fluidPairs<false>(in, spiky, g, softening, to);
          float gx = sums.gx, gy = sums.gy, gz = sums.gz;
          const float squares = sums.squares, cubes = sums.cubes;
          s.pairs.add(row, thread, count);
          s.pairCount[i] = count;
          const BoundarySums wall =
              wallPairs ? boundaryCandidates<true>(xi, yi, zi, bb, spiky, g, tw)
                        : boundaryCandidates<false>(xi, yi, zi, bb, spiky, g, tw);
          if (wallPairs) {
            PackedWallPairs& packed = wallPacking[thread];
            packed.resize(bb.padded);
            const std::uint32_t walls =
                packPairs(bb.padded, bb.field[3].data(), tw,
                          {packed.index.data(), packed.gx.data(), packed.gy.data(),
                           packed.gz.data(), packed.hr.data()});
            packed.storeRecords(
                walls, s.wallPairs.room(row, thread, PackedWallPairs::recordsWritten(walls)));
            s.wallPairs.add(row, thread, walls);
            s.wallPairCount[i] = walls;
          }
          const float bx = wall.gx, by = wall.gy, bz = wall.gz, bcubes = wall.cubes,
                      bweight = wall.weight;
          const float rho = densityScale * (self + cubes + bcubes);
          f.rho[i] = rho;
          s.inverseDensity[i] = 1.0f / rho;
          s.wallWeight[i] = bweight;
          s.gradientMoment[i] = momentScale * (sums.moment + wall.moment);
          gx = g * (gx + bx), gy = g * (gy + by), gz = g * (gz + bz);
          s.gradientSumX[i] = gx, s.gradientSumY[i] = gy, s.gradientSumZ[i] = gz;
          const float denominator = gx * gx + gy * gy + gz * gz + g * g * squares;
          s.factor[i] = jacobiStep / std::max(denominator, floor);
        }
      });
  s.pairs.end();
  if (wallPairs) s.wallPairs.end();
  updateGradientCorrection(c);
}

}  // namespace sph::solver
