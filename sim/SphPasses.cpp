// The three SPH passes of a step (DESIGN.md, "The SPH stage"; Müller, Charypar & Gross 2003):
// density, equation of state, forces. Particles are sorted by cell, so the neighbours of a
// particle are the 9 contiguous index ranges forEachNeighbourRange() hands out; the inner loops
// run over such a range with `omp simd` so they vectorise, and each particle sums only into its
// own slot, in a fixed order, so runs are bit-reproducible.
//
// Boundary particles are fluid particles that do not move (Boundary.h): they have the fluid
// mass, a summation density and an EOS pressure, and enter the force as ordinary neighbours at
// rest: with the viscosity term (no-slip walls, the default) or without it (free slip).
#include <algorithm>
#include <cmath>

#include "sim/CellBatch.h"
#include "sim/Parallel.h"
#include "sim/Simulation.h"

namespace sph {
namespace {

// The density kernel W(r) divided by its constant factor, as a function of r^2: the part the
// neighbour loops evaluate. Spiky by default, poly6 as in seed 003 eq. (3) (SolverParams.h).
struct SpikyShape {
  float h;
  float operator()(float r2) const {
    const float d = std::max(h - std::sqrt(r2), 0.0f);
    return d * d * d;
  }
};
struct Poly6Shape {
  float h2;
  float operator()(float r2) const {
    const float d = std::max(h2 - r2, 0.0f);
    return d * d * d;
  }
};

// Sum over the points of `grid` (coordinates px, py, pz) of shape(|x - p|^2).
template <class Shape>
float kernelSum(float xi, float yi, float zi, const NeighbourGrid& grid, const float* px,
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

// Sum over a padded candidate batch of shape(|x - p|^2); padding lanes contribute 0.
template <class Shape, int N>
float batchSum(float xi, float yi, float zi, const CandidateBatch<N>& c, Shape shape) {
  const float* px = c.field[0].data();
  const float* py = c.field[1].data();
  const float* pz = c.field[2].data();
  float s = 0;
#pragma omp simd reduction(+ : s)
  for (std::size_t j = 0; j < c.padded; ++j) {
    const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
    s += shape(dx * dx + dy * dy + dz * dz);
  }
  return s;
}

// Calls f(shape, factor) with the solver's density kernel.
template <class F>
void withDensityKernel(const SolverParams& s, const Kernels& k, F&& f) {
  if (s.densityKernel == DensityKernel::Spiky) f(SpikyShape{k.h}, k.spikyFactor);
  else f(Poly6Shape{k.h2}, k.poly6Factor);
}

// Equation of state (DESIGN.md): Tait p = B((rho/rho0)^7 - 1) or linear p = k(rho - rho0),
// clamped at 0 unless the scene allows tension.
struct Eos {
  float rho0, k;
  bool tait, clamp;
  float operator()(float rho) const {
    float p;
    if (tait) {
      const float r = rho / rho0, r2 = r * r, r3 = r2 * r;
      p = k * (r3 * r3 * r - 1.0f);
    } else {
      p = k * (rho - rho0);
    }
    return clamp ? std::max(p, 0.0f) : p;
  }
};

}  // namespace

// Boundary-boundary part of each boundary particle's density: fixed, so computed once.
void Simulation::computeStaticBoundaryDensity() {
  const BoundaryParticles& b = boundary_.particles();
  const NeighbourGrid& bgrid = boundary_.grid();
  boundaryStaticDensity_.resize(b.size());
  withDensityKernel(scene_.solver, derived_.kernels, [&](auto shape, float factor) {
    const float scale = factor * derived_.mass * derived_.densityNormalisation;
    parallelFor(b.size(), [&](std::size_t i) {
      boundaryStaticDensity_[i] =
          scale * kernelSum(b.x[i], b.y[i], b.z[i], bgrid, b.x.data(), b.y.data(), b.z.data(), shape);
    });
  });
  boundaryDensity_ = boundaryStaticDensity_;
  boundaryPressureTerm_.assign(b.size(), 0.0f);
}

// rho_i = sum_j m W(x_i - x_j) over fluid and boundary neighbours, the particle itself included
// (seed 003, eq. (1)); then the same sum for the boundary particles the fluid can reach.
void Simulation::computeDensity() {
  Particles& f = fluid_;
  const BoundaryParticles& b = boundary_.particles();
  const NeighbourGrid& bgrid = boundary_.grid();
  withDensityKernel(scene_.solver, derived_.kernels, [&](auto shape, float factor) {
    const float scale = factor * derived_.mass * derived_.densityNormalisation;
    forEachCellWithCandidates<3, 3>(
        grid_, {f.x.data(), f.y.data(), f.z.data()}, bgrid, {b.x.data(), b.y.data(), b.z.data()},
        derived_.h, [&](std::uint32_t begin, std::uint32_t end, const CandidateBatch<3>& fb,
                        const CandidateBatch<3>& bb) {
          for (std::uint32_t i = begin; i < end; ++i) {
            f.rho[i] = scale * (batchSum(f.x[i], f.y[i], f.z[i], fb, shape) +
                                batchSum(f.x[i], f.y[i], f.z[i], bb, shape));
          }
        });
    if (b.size() == 0 || f.size() == 0) return;
    // Boundary particles within reach of the fluid: the boundary cells overlapping the fluid
    // grid's box grown by one cell. The others keep their last values; no fluid particle is close
    // enough for those to matter (their kernel weight is exactly 0).
    const CellCoord o = grid_.origin(), n = grid_.dims();
    const float c = grid_.cellSize();
    const CellCoord lo = bgrid.cellOf((o[0] - 1) * c, (o[1] - 1) * c, (o[2] - 1) * c);
    const CellCoord hi = bgrid.cellOf((o[0] + n[0] + 1) * c, (o[1] + n[1] + 1) * c, (o[2] + n[2] + 1) * c);
    const CellCoord bo = bgrid.origin(), bn = bgrid.dims();
    int from[3], to[3];
    for (int a = 0; a < 3; ++a) {
      from[a] = std::max(lo[a] - bo[a], 0);
      to[a] = std::min(hi[a] - bo[a], bn[a] - 1);
      if (from[a] > to[a]) return;
    }
    const int rowsY = to[1] - from[1] + 1, rows = rowsY * (to[2] - from[2] + 1);
    parallelFor(static_cast<std::size_t>(rows), [&](std::size_t row) {
      const int j = from[1] + static_cast<int>(row) % rowsY, k = from[2] + static_cast<int>(row) / rowsY;
      const std::uint32_t begin = bgrid.cellBegin(bgrid.localIndex(from[0], j, k));
      const std::uint32_t end = bgrid.cellEnd(bgrid.localIndex(to[0], j, k));
      for (std::uint32_t q = begin; q < end; ++q) {
        boundaryDensity_[q] = boundaryStaticDensity_[q] +
                              scale * kernelSum(b.x[q], b.y[q], b.z[q], grid_, f.x.data(), f.y.data(),
                                                f.z.data(), shape);
      }
    });
  });
}

// Equation of state for fluid and boundary particles; also caches p / rho^2 and 1 / rho, the
// per-neighbour factors of the force pass, so that pass does no division per pair.
void Simulation::computePressure() {
  Particles& f = fluid_;
  const std::size_t n = f.size();
  pressureTerm_.resize(n);
  inverseDensity_.resize(n);
  const Eos eos{scene_.solver.restDensity, derived_.stiffness,
                scene_.solver.eos == EquationOfState::Tait, scene_.solver.clampNegativePressure};
  parallelFor(n, [&](std::size_t i) {
    const float p = eos(f.rho[i]);
    const float inv = 1.0f / f.rho[i];
    f.p[i] = p;
    inverseDensity_[i] = inv;
    pressureTerm_[i] = p * inv * inv;
  });
  parallelFor(boundaryDensity_.size(), [&](std::size_t q) {
    const float rho = boundaryDensity_[q];
    boundaryPressureTerm_[q] = rho > 0 ? eos(rho) / (rho * rho) : 0.0f;
  });
}

// a_i = - c sum_j m (p_i/rho_i^2 + p_j/rho_j^2) gradW_spiky(x_i - x_j)  fluid and boundary j
//       + nu (rho0/rho_i) sum_j m/rho_j (v_j - v_i) lapW_visc           fluid j (Müller 2003),
//                                                                        and walls if no-slip
//       + g
// with c the lattice gradient correction (SceneSetup.h).
// Pairs are antisymmetric term by term, so total momentum is conserved up to round-off.
void Simulation::computeForces() {
  Particles& f = fluid_;
  const BoundaryParticles& b = boundary_.particles();
  const NeighbourGrid& bgrid = boundary_.grid();
  const Kernels& kern = derived_.kernels;
  const float h = kern.h, h2 = kern.h2;
  const float pressureScale = -derived_.gradientCorrection * derived_.mass * kern.spikyGradFactor;
  const float viscScale = derived_.viscosity * scene_.solver.restDensity * derived_.mass *
                          kern.viscLapFactor;
  const Vec3 g = scene_.solver.gravity;
  const float noSlip = scene_.solver.noSlipWalls ? 1.0f / scene_.solver.restDensity : 0.0f;

  forEachCellWithCandidates<8, 4>(
      grid_,
      {f.x.data(), f.y.data(), f.z.data(), f.vx.data(), f.vy.data(), f.vz.data(),
       pressureTerm_.data(), inverseDensity_.data()},
      bgrid, {b.x.data(), b.y.data(), b.z.data(), boundaryPressureTerm_.data()}, h,
      [&](std::uint32_t begin, std::uint32_t end, const CandidateBatch<8>& fb,
          const CandidateBatch<4>& bb) {
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
          const float pi = pressureTerm_[i];
          float px = 0, py = 0, pz = 0, vx = 0, vy = 0, vz = 0;
#pragma omp simd reduction(+ : px, py, pz, vx, vy, vz)
          for (std::size_t j = 0; j < fb.padded; ++j) {
            const float dx = xi - fx[j], dy = yi - fy[j], dz = zi - fz[j];
            const float r2 = dx * dx + dy * dy + dz * dz;
            const bool inside = r2 < h2 && r2 > 0.0f;
            const float r = std::sqrt(r2);
            const float hr = inside ? h - r : 0.0f;
            const float invR = inside ? 1.0f / r : 0.0f;
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
            const bool inside = r2 < h2 && r2 > 0.0f;
            const float r = std::sqrt(r2);
            const float hr = inside ? h - r : 0.0f;
            const float invR = inside ? 1.0f / r : 0.0f;
            const float sp = (pi + bterm[j]) * hr * hr * invR;
            px += sp * dx, py += sp * dy, pz += sp * dz;
            w += hr;
          }
          // No-slip: the viscosity term with the wall at rest (v_b = 0, rho_b = rho0).
          const float drag = noSlip * w;
          vx -= drag * vxi, vy -= drag * vyi, vz -= drag * vzi;
          const float visc = viscScale * inverseDensity_[i];
          f.ax[i] = pressureScale * px + visc * vx + g.x();
          f.ay[i] = pressureScale * py + visc * vy + g.y();
          f.az[i] = pressureScale * pz + visc * vz + g.z();
        }
      });
}

}  // namespace sph
