// WCSPH's walls that hold pressure. The boundary particles of Boundary.h push with the pressure of
// their own summation density: the wall is then part of the fluid's energy (it conserves it, as
// tests/test_energy.cpp checks), but its pressure reads the wall's lattice and the fluid's packing
// beside it, not the water's weight: in the tests' still tank the floor's first layer pushed 1-3%
// too hard and the fluid's bottom layer read from -0.5% to -1.4% depending on the arithmetic's
// last bits (docs/benchmarks.md, "Walls that hold pressure").
//
// The pressure a wall should hold is what the fluid around it extrapolates to it, with the
// hydrostatic term (Adami, Hu & Adams 2012, "A generalized wall boundary condition for smoothed
// particle hydrodynamics", eq. 27, walls at rest):
//
//   p_b* = sum_f W_bf (p_f + rho_f g . (x_b - x_f)) / sum_f W_bf.
//
// Used as the wall's pressure directly it is not the gradient of any energy, and the closed
// sloshing tank of test_energy gains 11x its kinetic energy in 0.4 s (docs/notes/
// 2026-11-29-wcsph-walls-adami.md). So the wall keeps its summation pressure, which answers the
// fluid's approach at once, plus a correction that follows the gap to p_b* slowly:
//
//   p_b = p(rho_b) + sum_f w_bf s_f,   w_bf = W_bf / sum_f W_bf,
//
// where s_f is a share each fluid particle carries (warmStart.wallShare), moved every step toward
// the mean gap r_b = p_b* - p_b of the walls within its reach, at rate dt / tau with
// tau = 50 h / c (about 125 steps), and pulled back toward 0 at a tenth of that rate:
//
//   s_f += (dt / tau) (sum_b W_bf r_b / sum_b W_bf - 0.1 s_f);   s_f = 0 with no wall in reach.
//
// At rest the walls converge to the extrapolated pressure; in motion the correction lags the
// fluid by tau, and the coupling that made the direct extrapolation gain energy is too slow to
// feed the fluid's oscillations (test_energy's tank decays down to tau = 5 h / c). The shares
// live on the fluid particles rather than on the walls because the fluid's per-particle state
// already moves with its particles between ranks and into the cache's resume record; the pull
// toward 0 keeps the shares bounded where neighbouring walls ask for different corrections (a
// corner, the deep layers): without it a still tank's particles jumped at up to 13 cm/s.
//
// On K processes a wall particle beside the slab's face has fluid neighbours in the second plane
// of ghosts, whose p and rho this rank did not compute: their owners send them first. Every sum
// runs over the grid's cell ranges in the single process's order, so the walls keep their bits.
#include "sim/solver/WcsphWalls.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "sim/Parallel.h"
#include "sim/grid/CellBatch.h"
#include "sim/ranks/Halo.h"
#include "sim/solver/BoundaryReach.h"
#include "sim/solver/Kernels.h"
#include "sim/solver/SphPasses.h"

namespace sph::solver {
namespace {

// The shares' rate (tau = kTauSteps h / c) and their pull toward 0 (a fraction of that rate).
constexpr float kTauSteps = 50.0f;
constexpr float kPullToZero = 0.1f;

}  // namespace

void correctWallPressure(StepContext& c) {
  Particles& f = c.fluid;
  const BoundaryParticles& b = c.boundary.particles();
  BoundaryFields& bf = c.boundaryFields;
  std::vector<float>& share = c.warmStart.wallShare;
  share.resize(f.size(), 0.0f);
  bf.wallResidual.assign(b.size(), 0.0f);
  bf.wallReach.assign(b.size(), 0.0f);
  if (c.halo) c.halo->refreshGhosts({&f.p, &f.rho});
  const grid::NeighbourGrid& grid = c.grid;
  const grid::NeighbourGrid& bgrid = c.boundary.grid();
  const Vec3 g = c.solver.gravity;
  const float gx = g.x(), gy = g.y(), gz = g.z();
  const bool clamp = c.solver.clampNegativePressure;
  const float rate = std::min(c.dt * c.derived.speedOfSound / (kTauSteps * c.derived.h), 1.0f);
  withDensityShape(c.solver.densityKernel, c.derived.kernels, [&](auto shape, float factor) {
    const float scale = factor * c.derived.mass * c.derived.densityNormalisation;
    forEachBoundaryParticleNearFluid(c, [&](std::uint32_t q) {
      const float xq = b.x[q], yq = b.y[q], zq = b.z[q];
      float weight = 0, extrapolated = 0, shares = 0;
      grid.forEachNeighbourRange(
          grid.cellOf(xq, yq, zq), [&](std::uint32_t begin, std::uint32_t end) {
            float w = 0, e = 0, s = 0;
#pragma omp simd reduction(+ : w, e, s)
            for (std::uint32_t j = begin; j < end; ++j) {
              const float dx = xq - f.x[j], dy = yq - f.y[j], dz = zq - f.z[j];
              const float wj = shape(dx * dx + dy * dy + dz * dz);
              w += wj;
              e += wj * (f.p[j] + f.rho[j] * (gx * dx + gy * dy + gz * dz));
              s += wj * share[j];
            }
            weight += w, extrapolated += e, shares += s;
          });
      // The boundary particle's summation density and its pressure (computeDensity() and
      // computePressure() leave both to this pass), in the same arithmetic as theirs.
      const float rho = bf.staticDensity[q] + scale * weight;
      const float own = equationOfState(c, rho);
      bf.density[q] = rho;
      bf.pressureTerm[q] = rho > 0 ? own / (rho * rho) : 0.0f;
      if (!(weight > 0)) return;
      const float p = own + shares / weight;
      bf.pressureTerm[q] = (clamp ? std::max(p, 0.0f) : p) / (rho * rho);
      const float target = extrapolated / weight;
      bf.wallResidual[q] = (clamp ? std::max(target, 0.0f) : target) - p;
      bf.wallReach[q] = weight / shape(0.0f);
    });
    // Each fluid particle's walls: the boundary cells around its cell, gathered once per cell
    // (most cells have none, and their particles' shares are 0).
    const bool sameLattice = bgrid.cellSize() == grid.cellSize();
    const grid::CellCoord dims = grid.dims(), origin = grid.origin();
    parallelFor(grid::rowCount(grid), [&](std::size_t row) {
      std::vector<std::pair<std::uint32_t, std::uint32_t>> walls;
      const int j = static_cast<int>(row % dims[1]), k = static_cast<int>(row / dims[1]);
      for (int cx = 0; cx < dims[0]; ++cx) {
        const std::size_t cell = grid.localIndex(cx, j, k);
        const std::uint32_t begin = grid.cellBegin(cell), end = grid.cellEnd(cell);
        if (begin == end) continue;
        walls.clear();
        auto gather = [&](std::uint32_t from, std::uint32_t to) {
          if (from < to) walls.emplace_back(from, to);
        };
        for (std::uint32_t i = begin; i < end; ++i) {
          if (!sameLattice) {  // another cell size than the fluid's: the particle's own cells
            walls.clear();
            bgrid.forEachNeighbourRange(bgrid.cellOf(f.x[i], f.y[i], f.z[i]), gather);
          } else if (i == begin) {
            bgrid.forEachNeighbourRange({origin[0] + cx, origin[1] + j, origin[2] + k}, gather);
          }
          const float xi = f.x[i], yi = f.y[i], zi = f.z[i];
          float weight = 0, gap = 0;
          for (const auto& [from, to] : walls) {
            float w = 0, r = 0;
#pragma omp simd reduction(+ : w, r)
            for (std::uint32_t q = from; q < to; ++q) {
              const float dx = xi - b.x[q], dy = yi - b.y[q], dz = zi - b.z[q];
              const float wq = bf.wallReach[q] * shape(dx * dx + dy * dy + dz * dz);
              w += wq;
              r += wq * bf.wallResidual[q];
            }
            weight += w, gap += r;
          }
          share[i] = weight > 0 ? share[i] + rate * (gap / weight - kPullToZero * share[i]) : 0.0f;
        }
      }
    });
  });
}

}  // namespace sph::solver
