// The boundary particles the fluid can reach this step: those in the boundary cells that overlap
// the fluid grid's box grown by one cell. The others have no fluid particle within h, so their
// kernel weights are exactly 0 and the passes skip them.
#pragma once

#include <algorithm>
#include <cstdint>

#include "sim/Parallel.h"
#include "sim/solver/StepContext.h"

namespace sph::solver {

// Calls body(q) for every boundary particle the fluid can reach, in parallel by rows of boundary
// cells (each q once, so bodies that write only q's own slots need no synchronisation).
template <class Body>
void forEachBoundaryParticleNearFluid(const StepContext& c, Body&& body) {
  const grid::NeighbourGrid& grid = c.grid;
  const grid::NeighbourGrid& bgrid = c.boundary.grid();
  if (c.boundary.particles().size() == 0 || c.fluid.size() == 0) return;
  const grid::CellCoord o = grid.origin(), n = grid.dims();
  const float cs = grid.cellSize();
  const grid::CellCoord lo = bgrid.cellOf((o[0] - 1) * cs, (o[1] - 1) * cs, (o[2] - 1) * cs);
  const grid::CellCoord hi =
      bgrid.cellOf((o[0] + n[0] + 1) * cs, (o[1] + n[1] + 1) * cs, (o[2] + n[2] + 1) * cs);
  const grid::CellCoord bo = bgrid.origin(), bn = bgrid.dims();
  int from[3], to[3];
  for (int a = 0; a < 3; ++a) {
    from[a] = std::max(lo[a] - bo[a], 0);
    to[a] = std::min(hi[a] - bo[a], bn[a] - 1);
    if (from[a] > to[a]) return;
  }
  const int rowsY = to[1] - from[1] + 1, rows = rowsY * (to[2] - from[2] + 1);
  parallelFor(static_cast<std::size_t>(rows), [&](std::size_t row) {
    const int j = from[1] + static_cast<int>(row) % rowsY,
              k = from[2] + static_cast<int>(row) / rowsY;
    const std::uint32_t begin = bgrid.cellBegin(bgrid.localIndex(from[0], j, k));
    const std::uint32_t end = bgrid.cellEnd(bgrid.localIndex(to[0], j, k));
    for (std::uint32_t q = begin; q < end; ++q) body(q);
  });
}

}  // namespace sph::solver
