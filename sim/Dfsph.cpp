// Divergence-free SPH (Bender & Koschier 2015, "Divergence-free smoothed particle hydrodynamics";
// 2017, "Divergence-free SPH for incompressible and viscous fluids"): the pressure passes of
// solver.pressure = "dfsph". Written from the papers' equations; the notation follows 2017:
//
//   V_j = m / rho0 (every particle, fluid or boundary, has the fluid's mass), s_i = rho_i / rho0,
//   G_i = sum_j V_j gradW_ij over fluid and boundary neighbours,
//   alpha_i = 1 / (|G_i|^2 + sum_{fluid j} |V_j gradW_ij|^2)                        (2017, eq. 9)
//
// A pressure-like stiffness k_i (m^2/s^2) accelerates particle i by
//   a_i = - sum_{fluid j} V_j (k_i + k_j) gradW_ij - sum_{boundary b} V_b k_i gradW_ib
//       = - k_i G_i - sum_{fluid j} V_j k_j gradW_ij
// (boundary particles mirror the fluid particle's own stiffness, as Akinci et al. 2012 boundary
// particles do in the papers), and the rate of change of s_i for velocities v is
//   Ds_i/Dt = sum_{fluid j} V_j (v_i - v_j) . gradW_ij + sum_b V_b v_i . gradW_ib
//           = v_i . G_i - sum_{fluid j} V_j v_j . gradW_ij                       (walls at rest).
// So G_i, computed once per step with the factor, carries the boundary: the solver iterations
// loop over fluid neighbours only.
//
// Divergence-free solver (2017, Algorithm 2): k_i = alpha_i max(Ds_i/Dt, 0) / dt, until the mean
// dt Ds/Dt is at most max_divergence_error. Constant-density solver (Algorithm 3): with the
// predicted s*_i = s_i + dt Ds_i/Dt, k_i = alpha_i max(s*_i - 1, 0) / dt^2, until the mean
// s*_i - 1 is at most max_density_error. Both are Jacobi iterations (every k from the same
// velocities, then every velocity from the same k's) warm-started with half the last step's sums
// (jacobiSolve() says why half).
//
// The neighbours do not move within a step, so computeDfsphFactor() stores every fluid pair with
// its V_j gradW_ij once (StepScratch::pairRows), and each Jacobi pass is a gather over that list
// instead of a neighbour search with the kernel recomputed (3x faster per pass on the peer's dam
// break, docs/benchmarks.md).
//
// Built with -ffast-math like SphPasses.cpp (sim/CMakeLists.txt), under the same rules: every
// per-particle computation runs in a cell-range loop of forEachCellWithCandidates (the same split
// whatever the thread count), and the error means are serial sums in a fixed order.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "sim/CellBatch.h"
#include "sim/Parallel.h"
#include "sim/SphPasses.h"

namespace sph {
namespace {

// V gradW_spiky(x_i - x_j) = gradScale (h - r)^2 / r (x_i - x_j): the exact gradient of the
// normalised density sum over rho0 (SphPasses.cpp, computeDensity()).
float gradientScale(const StepContext& c) {
  return c.derived.kernels.spikyGradFactor * c.derived.mass * c.derived.densityNormalisation /
         c.solver.restDensity;
}

// The same 32 bits as another type (std::bit_cast, C++20).
template <class To, class From>
To bitsAs(From from) {
  static_assert(sizeof(To) == sizeof(From));
  To to;
  std::memcpy(&to, &from, sizeof(to));
  return to;
}

// Serial mean of `v` over the fluid: a fixed order, so the same bits for any thread count.
double meanOf(const std::vector<float>& v, std::size_t n) {
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += v[i];
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

// Calls body(i, index, gx, gy, gz, count) for every fluid particle, in parallel by rows of cells,
// with its `count` pairs (StepScratch::pairRows; computeDfsphFactor() built them this step).
template <class Body>
void forEachParticlePairs(const StepContext& c, Body&& body) {
  const StepScratch& s = c.scratch;
  parallelForDynamic(rowCount(c.grid), 4, [&](std::size_t row) {
    const auto [begin, end] = rowRange(c.grid, row);
    const StepScratch::PairRow& r = s.pairRows[row];
    std::size_t at = 0;
    for (std::uint32_t i = begin; i < end; ++i) {
      const std::uint32_t count = s.pairCount[i];
      body(i, r.index.data() + at, r.gx.data() + at, r.gy.data() + at, r.gz.data() + at, count);
      at += count;
    }
  });
}

// One source pass: for every particle the rate Ds_i/Dt of the current velocities (1/s), turned
// by `source(i, rate)` into the solver's source term and stiffness.
template <class Source>
void sourcePass(StepContext& c, Source&& source) {
  Particles& f = c.fluid;
  const StepScratch& s = c.scratch;
  const float* vx = f.vx.data();
  const float* vy = f.vy.data();
  const float* vz = f.vz.data();
  forEachParticlePairs(c, [&](std::uint32_t i, const std::uint32_t* index, const float* gx,
                              const float* gy, const float* gz, std::uint32_t count) {
    float sum = 0;
#pragma omp simd reduction(+ : sum)
    for (std::uint32_t q = 0; q < count; ++q) {
      const std::uint32_t j = index[q];
      sum += vx[j] * gx[q] + vy[j] * gy[q] + vz[j] * gz[q];
    }
    const float rate =
        vx[i] * s.gradientSumX[i] + vy[i] * s.gradientSumY[i] + vz[i] * s.gradientSumZ[i] - sum;
    source(i, rate);
  });
}

// One velocity pass: v_i -= dt (k_i G_i + sum_j V_j k_j gradW_ij), the stiffness of the last
// source pass; adds it to `warm` (and, with `acceleration`, the pressure acceleration to a).
void velocityPass(StepContext& c, std::vector<float>& warm, bool acceleration) {
  Particles& f = c.fluid;
  const StepScratch& s = c.scratch;
  const float* k = s.stiffness.data();
  const float dt = c.dt;
  forEachParticlePairs(c, [&](std::uint32_t i, const std::uint32_t* index, const float* gx,
                              const float* gy, const float* gz, std::uint32_t count) {
    float ax = 0, ay = 0, az = 0;
#pragma omp simd reduction(+ : ax, ay, az)
    for (std::uint32_t q = 0; q < count; ++q) {
      const float kj = k[index[q]];
      ax += kj * gx[q], ay += kj * gy[q], az += kj * gz[q];
    }
    const float ki = k[i];
    const float px = -(ki * s.gradientSumX[i] + ax);
    const float py = -(ki * s.gradientSumY[i] + ay);
    const float pz = -(ki * s.gradientSumZ[i] + az);
    f.vx[i] += dt * px, f.vy[i] += dt * py, f.vz[i] += dt * pz;
    if (acceleration) f.ax[i] += px, f.ay[i] += py, f.az[i] += pz;
    warm[i] += ki;
  });
}

// Makes the warm-start arrays follow the fluid (new particles start from 0).
void sizeWarmStart(StepContext& c) {
  c.warmStart.density.resize(c.fluid.size(), 0.0f);
  c.warmStart.divergence.resize(c.fluid.size(), 0.0f);
}

// A Jacobi solve: warm start from `warm` (which then collects this step's sum), then iterations
// of source and velocity passes until `error()` (a fraction) is at most `tolerance` after at
// least `minIterations`, or `maxIterations`. `rate(i, rate)` sets source[i] and stiffness[i].
// Returns the iterations and the error reached.
template <class Rate>
std::pair<int, double> jacobiSolve(StepContext& c, std::vector<float>& warm, double tolerance,
                                   int minIterations, int maxIterations, bool acceleration,
                                   Rate&& rate) {
  const std::size_t n = c.fluid.size();
  StepScratch& s = c.scratch;
  s.source.resize(n);
  s.stiffness.resize(n);
  bool warmed = false;
  for (std::size_t i = 0; i < n; ++i) warmed = warmed || warm[i] != 0.0f;
  if (warmed) {
    // Half the last step's sum: every iteration adds a non-negative stiffness (only compression
    // is corrected), so a full warm start could only grow from step to step, never relax.
    std::transform(warm.begin(), warm.end(), s.stiffness.begin(), [](float k) { return 0.5f * k; });
    std::fill(warm.begin(), warm.end(), 0.0f);
    velocityPass(c, warm, acceleration);
  } else {
    std::fill(warm.begin(), warm.end(), 0.0f);
  }
  int iterations = 0;
  double error = 0;
  while (true) {
    sourcePass(c, rate);
    error = meanOf(s.source, n);
    if ((error <= tolerance && iterations >= minIterations) || iterations >= maxIterations) break;
    velocityPass(c, warm, acceleration);
    ++iterations;
  }
  return {iterations, error};
}

// sum_j |V gradW_ij|^2 for a particle inside the rest lattice (where G_i = 0): the scale of
// alpha's denominator for a full neighbourhood.
float latticeDenominator(const StepContext& c) {
  const float dx = c.solver.spacing, h = c.derived.h, g = gradientScale(c);
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

}  // namespace

// G_i and alpha_i from the positions of this step (after computeDensity()), and the fluid pairs
// with their V gradW_ij for the solvers' iterations (StepScratch::pairRows).
void computeDfsphFactor(StepContext& c) {
  Particles& f = c.fluid;
  const BoundaryParticles& b = c.boundary.particles();
  StepScratch& s = c.scratch;
  const std::size_t n = f.size();
  s.gradientSumX.resize(n), s.gradientSumY.resize(n), s.gradientSumZ.resize(n);
  s.factor.resize(n);
  s.pairCount.resize(n);
  if (s.indexBits.size() < n) {  // the bits of i: unchanged by the sort, so set once
    const std::size_t from = s.indexBits.size();
    s.indexBits.resize(n);
    for (std::size_t i = from; i < n; ++i)
      s.indexBits[i] = bitsAs<float>(static_cast<std::uint32_t>(i));
  }
  s.pairRows.resize(std::max(s.pairRows.size(), rowCount(c.grid)));
  for (StepScratch::PairRow& r : s.pairRows) r.used = 0;
  sizeWarmStart(c);
  const SpikyPairShape spiky{c.derived.h, c.derived.h * c.derived.h};
  const float g = gradientScale(c);
  // A floor under alpha's denominator: a particle with a sparse neighbourhood (a drop touching a
  // wall at the edge of the support) has a tiny one, and its stiffness, acting on its few
  // neighbours through their gradients rather than its own, blew up runs. A quarter of the full
  // neighbourhood's value leaves every particle with half a neighbourhood or more (the free
  // surface) untouched and under-corrects only spray.
  const float floor = 0.25f * latticeDenominator(c);
  // Per thread: each candidate's V gradW_ij (0 outside the support) and index, before the
  // candidates inside the support are packed into the row.
  std::vector<CandidateBatch<4>> gradients(threadCount());
  forEachCellWithCandidates<4, 3>(
      c.grid, {f.x.data(), f.y.data(), f.z.data(), s.indexBits.data()}, c.boundary.grid(),
      {b.x.data(), b.y.data(), b.z.data()}, c.derived.h,
      [&](std::size_t row, std::uint32_t begin, std::uint32_t end, const CandidateBatch<4>& fb,
          const CandidateBatch<3>& bb) {
        CandidateBatch<4>& t = gradients[threadIndex()];
        t.resize(fb.padded);
        float* tx = t.field[0].data();
        float* ty = t.field[1].data();
        float* tz = t.field[2].data();
        float* tw = t.field[3].data();
        StepScratch::PairRow& pairs = s.pairRows[row];
        const float* fx = fb.field[0].data();
        const float* fy = fb.field[1].data();
        const float* fz = fb.field[2].data();
        for (std::uint32_t i = begin; i < end; ++i) {
          const float xi = f.x[i], yi = f.y[i], zi = f.z[i];
          float gx = 0, gy = 0, gz = 0, squares = 0;
#pragma omp simd reduction(+ : gx, gy, gz, squares)
          for (std::size_t j = 0; j < fb.padded; ++j) {
            const float dx = xi - fx[j], dy = yi - fy[j], dz = zi - fz[j];
            const float r2 = dx * dx + dy * dy + dz * dz;
            const float invR = spiky.inverseDistance(r2);
            const float hr = spiky.hMinusR(r2, invR);
            const float wj = hr * hr * invR;
            tw[j] = wj;
            tx[j] = g * wj * dx, ty[j] = g * wj * dy, tz[j] = g * wj * dz;
            gx += wj * dx, gy += wj * dy, gz += wj * dz;
            squares += wj * wj * r2;
          }
          // The pairs: the candidates inside the support (w > 0; the particle itself has w = 0),
          // packed without a branch.
          const std::size_t at = pairs.used;
          pairs.makeRoom(at + fb.count);
          std::uint32_t* pi = pairs.index.data() + at;
          float* px = pairs.gx.data() + at;
          float* py = pairs.gy.data() + at;
          float* pz = pairs.gz.data() + at;
          const float* bits = fb.field[3].data();
          std::uint32_t count = 0;
          for (std::size_t j = 0; j < fb.count; ++j) {
            pi[count] = bitsAs<std::uint32_t>(bits[j]);
            px[count] = tx[j], py[count] = ty[j], pz[count] = tz[j];
            count += tw[j] != 0.0f ? 1u : 0u;
          }
          pairs.used = at + count;
          s.pairCount[i] = count;
          float bx = 0, by = 0, bz = 0;
#pragma omp simd reduction(+ : bx, by, bz)
          for (std::size_t j = 0; j < bb.padded; ++j) {
            const float dx = xi - bb.field[0][j], dy = yi - bb.field[1][j],
                        dz = zi - bb.field[2][j];
            const float r2 = dx * dx + dy * dy + dz * dz;
            const float invR = spiky.inverseDistance(r2);
            const float hr = spiky.hMinusR(r2, invR);
            const float wb = hr * hr * invR;
            bx += wb * dx, by += wb * dy, bz += wb * dz;
          }
          gx = g * (gx + bx), gy = g * (gy + by), gz = g * (gz + bz);
          s.gradientSumX[i] = gx, s.gradientSumY[i] = gy, s.gradientSumZ[i] = gz;
          const float denominator = gx * gx + gy * gy + gz * gz + g * g * squares;
          s.factor[i] = 1.0f / std::max(denominator, floor);
        }
      });
}

// Divergence-free solver: makes Ds/Dt = 0 for the velocities at the start of the step (2017,
// Algorithm 2; the papers run it at the end of a step, on the same positions and velocities).
void solveDivergence(StepContext& c) {
  StepScratch& s = c.scratch;
  const float invDt = 1.0f / c.dt, dt = c.dt;
  const auto [iterations, error] =
      jacobiSolve(c, c.warmStart.divergence, c.solver.maxDivergenceError * 0.01, 1,
                  c.solver.maxDivergenceIterations, false, [&](std::uint32_t i, float rate) {
                    const float r = std::max(rate, 0.0f);
                    s.source[i] = dt * r;
                    s.stiffness[i] = s.factor[i] * r * invDt;
                  });
  c.solveStats.divergenceIterations = iterations;
  c.solveStats.divergenceError = static_cast<float>(100 * error);
  c.solveStats.totalDivergenceIterations += static_cast<std::uint64_t>(iterations);
}

// Constant-density solver on the velocities after the non-pressure forces (2017, Algorithm 3);
// the pressure acceleration is added to a, and for output p_i, the pressure that gives the same
// force in the WCSPH formula.
void solveDensity(StepContext& c) {
  Particles& f = c.fluid;
  StepScratch& s = c.scratch;
  const float rho0 = c.solver.restDensity;
  const float invRho0 = 1.0f / rho0, dt = c.dt, invDt2 = 1.0f / (c.dt * c.dt);
  const auto [iterations, error] = jacobiSolve(
      c, c.warmStart.density, c.solver.maxDensityError * 0.01, c.solver.minDensityIterations,
      c.solver.maxDensityIterations, true, [&](std::uint32_t i, float rate) {
        const float e = std::max(f.rho[i] * invRho0 + dt * rate - 1.0f, 0.0f);
        s.source[i] = e;
        s.stiffness[i] = s.factor[i] * e * invDt2;
      });
  c.solveStats.densityIterations = iterations;
  c.solveStats.densityError = static_cast<float>(100 * error);
  c.solveStats.totalDensityIterations += static_cast<std::uint64_t>(iterations);
  c.solveStats.steps += 1;
  // The WCSPH force is c sum m (p_i/rho_i^2 + p_j/rho_j^2) gradW_spiky (c the lattice gradient
  // correction); DFSPH's is sum (m/rho0) n (k_i + k_j) gradW_spiky (n the density normalisation):
  // the same force for p_i = rho_i^2 / rho0 (n / c) k_i.
  const float scale = invRho0 * c.derived.densityNormalisation / c.derived.gradientCorrection;
  const std::vector<float>& k = c.warmStart.density;
  for (std::size_t i = 0; i < f.size(); ++i) f.p[i] = f.rho[i] * f.rho[i] * scale * k[i];
}

}  // namespace sph
