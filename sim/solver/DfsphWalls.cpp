// DFSPH's walls that hold pressure. With Akinci et al. 2012's boundary particles as the DFSPH
// papers use them, a wall pair pushes with the fluid particle's stiffness alone (Dfsph.cpp,
// "a_i = ... - sum_b V_b k_i gradW_ib"): the wall carries no pressure of its own, so the fluid's
// first layer must hold twice its share and reads about twice hydrostatic, and the layers beside
// a side wall a quarter more. Here each boundary particle b the fluid reaches takes a stiffness
// of its own, extrapolated from the fluid around it as Adami, Hu & Adams 2012 do for the pressure
// ("A generalized wall boundary condition for smoothed particle hydrodynamics", eq. 27, walls at
// rest), in the DFSPH papers' stiffness k = p / rho (m^2/s^2):
//
//   k_b = sum_f k_f w_bf + g . sum_f w_bf (x_b - x_f),   w_bf = W_bf / sum_f W_bf,   k_b >= 0,
//
// and the pair pushes with both: a_i = ... - sum_b V_b (k_i + k_b) gradW_ib. The hydrostatic
// term (the density solver's only: it is the solve that holds the fluid up against gravity)
// carries the pressure from the neighbours' mean height down to the wall particle's.
//
// Inside a Jacobi solve (Dfsph.cpp, jacobiSolve()) the fluid's stiffness arrives in increments,
// so the wall's is recomputed from the fluid's sum so far at every iteration and the velocities
// take its change (clamped at 0 as a whole, not per increment). The factor alpha_i stays the
// papers': a wall particle's stiffness depends on i's only through one weight of many.
//
// W is (h - r)^3, the spiky kernel's shape: positive inside the support, and the weights only
// need to be relative. On K processes a wall particle beside the slab's face has fluid
// neighbours up to 2h from the rank's particles, in the second plane of ghosts, whose stiffness
// is not computed here: their owners send it before every wall pass (Dfsph.cpp), and the sums run
// over the neighbours in the single process's order, so they keep their bits.
#include "sim/solver/DfsphWalls.h"

#include <algorithm>
#include <cmath>

#include "sim/Parallel.h"
#include "sim/grid/CellBatch.h"

namespace sph::solver {

// A wall particle's fluid neighbours are its wall pairs seen from the other side: a counting sort
// of the step's wall pairs by boundary particle. Walked in the fluid's order (rows, then the
// particles of a row), each wall particle's list comes out in ascending fluid order, which on K
// processes is the single process's order restricted to the rank (sim/ranks/Halo.h), so the
// sums over it keep their bits. Sequential: it touches each pair twice, a small part of the step.
void findWallNeighbours(StepContext& c) {
  WallStiffness& w = c.walls;
  const StepScratch& s = c.scratch;
  const Particles& f = c.fluid;
  const BoundaryParticles& b = c.boundary.particles();
  const std::size_t rows = rowCount(c.grid);
  // Walks every wall pair: visit(fluid particle, boundary particle, h - r).
  auto forEachWallPair = [&](auto&& visit) {
    for (std::size_t row = 0; row < rows; ++row) {
      const auto [begin, end] = rowRange(c.grid, row);
      const grid::PairStore::Row r = s.wallPairs.row(row);
      std::size_t at = 0;
      for (std::uint32_t i = begin; i < end; ++i) {
        for (std::uint32_t q = 0; q < s.wallPairCount[i]; ++q, ++at)
          visit(i, r.pair[at].index, r.weight[at]);
      }
    }
  };
  std::vector<std::uint32_t>& cursor = w.cursor;  // per boundary particle
  cursor.assign(b.size(), 0);
  forEachWallPair([&](std::uint32_t, std::uint32_t q, float) { ++cursor[q]; });
  w.active.clear();
  w.start.assign(1, 0);
  for (std::size_t q = 0; q < b.size(); ++q) {
    if (cursor[q] == 0) continue;
    w.active.push_back(static_cast<std::uint32_t>(q));
    const std::uint32_t from = w.start.back();
    w.start.push_back(from + cursor[q]);
    cursor[q] = from;
  }
  const std::size_t n = w.active.size();
  w.neighbour.resize(w.start[n]);
  w.weight.resize(w.start[n]);
  forEachWallPair([&](std::uint32_t i, std::uint32_t q, float hr) {
    const std::uint32_t at = cursor[q]++;
    w.neighbour[at] = i, w.weight[at] = hr * hr * hr;
  });
  w.hydrostatic.resize(n);
  w.total.assign(n, 0.0f);
  w.change.resize(b.size());
  const Vec3 g = c.solver.gravity;
  parallelFor(n, [&](std::size_t a) {
    const std::uint32_t q = w.active[a];
    float sum = 0, sx = 0, sy = 0, sz = 0;  // sum W and sum W (x_b - x_f)
    for (std::uint32_t k = w.start[a]; k < w.start[a + 1]; ++k) {
      const std::uint32_t fi = w.neighbour[k];
      const float wf = w.weight[k];
      sum += wf, sx += wf * (b.x[q] - f.x[fi]), sy += wf * (b.y[q] - f.y[fi]),
          sz += wf * (b.z[q] - f.z[fi]);
    }
    const float inv = sum > 0 ? 1.0f / sum : 0.0f;
    for (std::uint32_t k = w.start[a]; k < w.start[a + 1]; ++k) w.weight[k] *= inv;
    w.hydrostatic[a] = inv * (g.x() * sx + g.y() * sy + g.z() * sz);
  });
}

void startWallSolve(StepContext& c) {
  c.walls.applied.assign(c.walls.active.size(), 0.0f);
}

void changeWallStiffness(StepContext& c, const std::vector<float>& applied,
                         const std::vector<float>& stiffness, bool hydrostatic) {
  WallStiffness& w = c.walls;
  parallelFor(w.active.size(), [&](std::size_t a) {
    float k = hydrostatic ? w.hydrostatic[a] : 0.0f;
    for (std::uint32_t q = w.start[a]; q < w.start[a + 1]; ++q) {
      const std::uint32_t f = w.neighbour[q];
      k += w.weight[q] * (applied[f] + stiffness[f]);
    }
    k = std::max(k, 0.0f);
    w.change[w.active[a]] = k - w.applied[a];
    w.applied[a] = k;
  });
}

void finishWallSolve(StepContext& c) {
  WallStiffness& w = c.walls;
  for (std::size_t a = 0; a < w.active.size(); ++a) w.total[a] += w.applied[a];
}

void storeWallPressure(StepContext& c) {
  const WallStiffness& w = c.walls;
  std::vector<float>& term = c.boundaryFields.pressureTerm;
  term.assign(c.boundary.particles().size(), 0.0f);
  // p / rho^2 of the WCSPH force that pushes as k does (Dfsph.cpp, solveDensity()).
  const float scale =
      c.derived.densityNormalisation / (c.solver.restDensity * c.gradientCorrection);
  for (std::size_t a = 0; a < w.active.size(); ++a) term[w.active[a]] = scale * w.total[a];
}

}  // namespace sph::solver
