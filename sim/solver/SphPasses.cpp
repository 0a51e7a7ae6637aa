// The neighbour passes of a step (DESIGN.md, "The SPH stage"; Müller, Charypar & Gross 2003):
// density and forces (the equation of state between them is in EquationOfState.cpp). Particles are
// sorted by cell, so the neighbours of a particle are the 9 contiguous index ranges
// forEachNeighbourRange() hands out; the inner loops run over such a range with `omp simd` so they
// vectorise, and each particle sums only into its own slot, in a fixed order, so runs are
// bit-reproducible.
//
// This file is built with -ffast-math (sim/CMakeLists.txt): reciprocal square roots are estimated
// in vector code but exact in scalar code, so every loop here must take the same path whatever
// the thread split. The batch loops run over padded lengths (always vector); the range loops run
// over cell ranges (the same split for any thread count). Element-wise loops, whose vector/scalar
// split moves with the thread chunks, live in files built without it.
//
// Boundary particles are fluid particles that do not move (Boundary.h): they have the fluid
// mass, a summation density and an EOS pressure, and enter the force as ordinary neighbours at
// rest: with the viscosity term (no-slip walls, the default) or without it (free slip).
#include <algorithm>
#include <cmath>

#include "sim/Parallel.h"
#include "sim/grid/CellBatch.h"
#include "sim/ranks/ExactSum.h"
#include "sim/solver/BoundaryReach.h"
#include "sim/solver/SphPasses.h"

namespace sph::solver {
namespace {

// Sum over the points of `grid` (coordinates px, py, pz) of shape(|x - p|^2).
template <class Shape>
float kernelSum(float xi, float yi, float zi, const grid::NeighbourGrid& grid, const float* px,
                const float* py, const float* pz, Shape shape) {
  float sum = 0;
  grid.forEachNeighbourRange(grid.cellOf(xi, yi, zi), [&](std::uint32_t begin, std::uint32_t end) {
    float s = 0;
#pragma omp simd reduction(+ : s)
    for (std::uint32_t j = begin; j < end; ++j) {
      const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
      s += shape(dx * dx + dy * dy + dz * dz);
    }
    sum += s;
  });
  return sum;
}

// Density sum of a candidate batch and, alongside, its share of the particle's gradient moment:
// sum (h - r)^2 r, the trace of sum_j (x_j - x_i) (x) gradW_spiky(x_i - x_j) up to -G.
template <class Shape, int N>
void batchDensityAndMoment(float xi, float yi, float zi, float h, const grid::CandidateBatch<N>& c,
                           Shape shape, float& density, float& moment) {
  const float* px = c.field[0].data();
  const float* py = c.field[1].data();
  const float* pz = c.field[2].data();
  float s = 0, t = 0;
#pragma omp simd reduction(+ : s, t)
  for (std::size_t j = 0; j < c.padded; ++j) {
    const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
    const float r2 = dx * dx + dy * dy + dz * dz;
    s += shape(r2);
    t += SpikyMomentShape{h}(r2);
  }
  density += s, moment += t;
}

}  // namespace

// The pressure force's scale c = 1 / mean K over the particles with a full neighbourhood (at
// least rest density): the lattice value (SceneSetup.h) corrected for how the particles are
// actually arranged. One factor for all pairs keeps momentum conserved; it drifts slowly, so
// energy is conserved as well as before. Without it a settled still tank carries ~3% excess
// pressure (the disordered packing's discrete gradient is that much weaker than the lattice's).
void updateGradientCorrection(StepContext& c) {
  const Particles& f = c.fluid;
  const std::vector<float>& gradientMoment = c.scratch.gradientMoment;
  const float rho0 = c.solver.restDensity;
  // Exact, so the same for any order of the terms and any split between ranks.
  ranks::ExactSum sum;
  std::int64_t count = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f.rho[i] < rho0 || (c.ghost && (*c.ghost)[i])) continue;
    sum.add(gradientMoment[i]);
    ++count;
  }
  if (c.ranks) ranks::sumOverRanks(*c.ranks, sum, count);
  constexpr std::int64_t kMinimumSample = 64;  // fewer: a spray or a drop; trust the lattice
  c.gradientCorrection = count >= kMinimumSample
                             ? static_cast<float>(static_cast<double>(count) / sum.toDouble())
                             : c.derived.gradientCorrection;
}


// Boundary-boundary part of each boundary particle's density: fixed, so computed once.
void computeStaticBoundaryDensity(StepContext& c) {
  const BoundaryParticles& b = c.boundary.particles();
  const grid::NeighbourGrid& bgrid = c.boundary.grid();
  BoundaryFields& bf = c.boundaryFields;
  bf.staticDensity.resize(b.size());
  withDensityShape(c.solver.densityKernel, c.derived.kernels, [&](auto shape, float factor) {
    const float scale = factor * c.derived.mass * c.derived.densityNormalisation;
    parallelFor(b.size(), [&](std::size_t i) {
      bf.staticDensity[i] = scale * kernelSum(b.x[i], b.y[i], b.z[i], bgrid, b.x.data(), b.y.data(),
                                              b.z.data(), shape);
    });
  });
  bf.density = bf.staticDensity;
  bf.pressureTerm.assign(b.size(), 0.0f);
}

void sortParticles(StepContext& c) {
  Particles& f = c.fluid;
  c.grid.build(f.x.data(), f.y.data(), f.z.data(), f.size(), c.derived.h, c.scratch.order);
  f.permute(c.scratch.order, c.scratch.permuteScratch);
  // The solvers' state is per particle too (new particles start from 0).
  for (std::vector<float>* warm : c.warmStart.fields()) {
    if (warm->empty()) continue;
    warm->resize(f.size(), 0.0f);
    std::vector<float>& out = c.scratch.pressureTerm;  // free until the pressure pass
    out.resize(f.size());
    const std::vector<std::uint32_t>& order = c.scratch.order;
    parallelFor(f.size(), [&](std::size_t i) { out[i] = (*warm)[order[i]]; });
    warm->swap(out);
  }
}

// rho_i = sum_j m W(x_i - x_j) over fluid and boundary neighbours, the particle itself included
// (seed 003, eq. (1)); then the same sum for the boundary particles the fluid can reach.
void computeDensity(StepContext& c) {
  Particles& f = c.fluid;
  const BoundaryParticles& b = c.boundary.particles();
  const grid::NeighbourGrid& bgrid = c.boundary.grid();
  const grid::NeighbourGrid& grid = c.grid;
  const DerivedParams& derived = c.derived;
  std::vector<float>& gradientMoment = c.scratch.gradientMoment;
  BoundaryFields& bf = c.boundaryFields;
  const float h = derived.h;
  // K_i = (1/3) sum_j V (x_j - x_i) . gradW(x_i - x_j), V = spacing^3: 1 on the rest lattice
  // once corrected (SceneSetup.h), a little off once the particles have rearranged.
  const float momentScale =
      -derived.kernels.spikyGradFactor * derived.mass / c.solver.restDensity / 3;
  gradientMoment.resize(f.size());
  withDensityShape(c.solver.densityKernel, derived.kernels, [&](auto shape, float factor) {
    const float scale = factor * derived.mass * derived.densityNormalisation;
    grid::forEachCellWithCandidates<3, 3>(
        grid, {f.x.data(), f.y.data(), f.z.data()}, bgrid, {b.x.data(), b.y.data(), b.z.data()},
        derived.h,
        [&](std::uint32_t begin, std::uint32_t end, const grid::CandidateBatch<3>& fb,
            const grid::CandidateBatch<3>& bb) {
          for (std::uint32_t i = begin; i < end; ++i) {
            float density = 0, moment = 0;
            batchDensityAndMoment(f.x[i], f.y[i], f.z[i], h, fb, shape, density, moment);
            batchDensityAndMoment(f.x[i], f.y[i], f.z[i], h, bb, shape, density, moment);
            f.rho[i] = scale * density;
            gradientMoment[i] = momentScale * moment;
          }
        });
    updateGradientCorrection(c);
    // Walls that hold the extrapolated pressure sum their density with the rest of their
    // neighbour sums (correctWallPressure()).
    if (c.solver.wallPressure == scene::WallPressure::Extrapolated) return;
    forEachBoundaryParticleNearFluid(c, [&](std::uint32_t q) {
      bf.density[q] =
          bf.staticDensity[q] + scale * kernelSum(b.x[q], b.y[q], b.z[q], grid, f.x.data(),
                                                  f.y.data(), f.z.data(), shape);
    });
  });
}

// a_i = - c sum_j m (p_i/rho_i^2 + p_j/rho_j^2) gradW_spiky(x_i - x_j)  fluid and boundary j
//       + nu (rho0/rho_i) sum_j m/rho_j (v_j - v_i) lapW_visc           fluid j (Müller 2003),
//                                                                        and walls if no-slip
//       + g
// with c the gradient correction (updateGradientCorrection()).
// Pairs are antisymmetric term by term, so total momentum is conserved up to round-off.
void computeForces(StepContext& c) {
  Particles& f = c.fluid;
  const BoundaryParticles& b = c.boundary.particles();
  const grid::NeighbourGrid& bgrid = c.boundary.grid();
  const Kernels& kern = c.derived.kernels;
  const std::vector<float>& pressureTerm = c.scratch.pressureTerm;
  const std::vector<float>& inverseDensity = c.scratch.inverseDensity;
  const float h = kern.h;
  const SpikyPairShape spiky{kern.h, kern.h2};
  const float pressureScale = -c.gradientCorrection * c.derived.mass * kern.spikyGradFactor;
  const float viscScale =
      c.derived.viscosity * c.solver.restDensity * c.derived.mass * kern.viscLapFactor;
  const Vec3 g = c.solver.gravity;
  const float noSlip = c.solver.noSlipWalls ? 1.0f / c.solver.restDensity : 0.0f;

  grid::forEachCellWithCandidates<8, 4>(
      c.grid,
      {f.x.data(), f.y.data(), f.z.data(), f.vx.data(), f.vy.data(), f.vz.data(),
       pressureTerm.data(), inverseDensity.data()},
      bgrid, {b.x.data(), b.y.data(), b.z.data(), c.boundaryFields.pressureTerm.data()}, h,
      [&](std::uint32_t begin, std::uint32_t end, const grid::CandidateBatch<8>& fb,
          const grid::CandidateBatch<4>& bb) {
        const float* fx = fb.field[0].data();
        const float* fy = fb.field[1].data();
        const float* fz = fb.field[2].data();
        const float* fvx = fb.field[3].data();
        const float* fvy = fb.field[4].data();
        const float* fvz = fb.field[5].data();
        const float* pterm = fb.field[6].data();
        const float* invRho = fb.field[7].data();
        const float* bx = bb.field[0].data();
        const float* by = bb.field[1].data();
        const float* bz = bb.field[2].data();
        const float* bterm = bb.field[3].data();
        for (std::uint32_t i = begin; i < end; ++i) {
          const float xi = f.x[i], yi = f.y[i], zi = f.z[i];
          const float vxi = f.vx[i], vyi = f.vy[i], vzi = f.vz[i];
          const float pi = pressureTerm[i];
          float px = 0, py = 0, pz = 0, vx = 0, vy = 0, vz = 0;
#pragma omp simd reduction(+ : px, py, pz, vx, vy, vz)
          for (std::size_t j = 0; j < fb.padded; ++j) {
            const float dx = xi - fx[j], dy = yi - fy[j], dz = zi - fz[j];
            const float r2 = dx * dx + dy * dy + dz * dz;
            const float invR = spiky.inverseDistance(r2);
            const float hr = spiky.hMinusR(r2, invR);
            const float sp = (pi + pterm[j]) * hr * hr * invR;
            const float sv = invRho[j] * hr;
            px += sp * dx, py += sp * dy, pz += sp * dz;
            vx += sv * (fvx[j] - vxi), vy += sv * (fvy[j] - vyi), vz += sv * (fvz[j] - vzi);
          }
          float w = 0;
#pragma omp simd reduction(+ : px, py, pz, w)
          for (std::size_t j = 0; j < bb.padded; ++j) {
            const float dx = xi - bx[j], dy = yi - by[j], dz = zi - bz[j];
            const float r2 = dx * dx + dy * dy + dz * dz;
            const float invR = spiky.inverseDistance(r2);
            const float hr = spiky.hMinusR(r2, invR);
            const float sp = (pi + bterm[j]) * hr * hr * invR;
            px += sp * dx, py += sp * dy, pz += sp * dz;
            w += hr;
          }
          // No-slip: the viscosity term with the wall at rest (v_b = 0, rho_b = rho0).
          const float drag = noSlip * w;
          vx -= drag * vxi, vy -= drag * vyi, vz -= drag * vzi;
          const float visc = viscScale * inverseDensity[i];
          f.ax[i] = pressureScale * px + visc * vx + g.x();
          f.ay[i] = pressureScale * py + visc * vy + g.y();
          f.az[i] = pressureScale * pz + visc * vz + g.z();
        }
      });
}

}  // namespace sph::solver
