#include "sim/run/StartSlab.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "sim/solver/Boundary.h"
#include "sim/grid/NeighbourGrid.h"
#include "sim/solver/SceneSetup.h"

namespace sph::run {
namespace {

// Calls visit(i, j, k) for the points of lattice l whose index along `axis` is in [t0, t1), in
// initialFluid's order (z slowest, x fastest).
template <class Visit>
void walk(const solver::FluidLattice& l, int axis, int t0, int t1, Visit&& visit) {
  int lo[3] = {0, 0, 0}, hi[3] = {l.n[0], l.n[1], l.n[2]};
  lo[axis] = t0, hi[axis] = t1;
  for (int k = lo[2]; k < hi[2]; ++k)
    for (int j = lo[1]; j < hi[1]; ++j)
      for (int i = lo[0]; i < hi[0]; ++i) visit(i, j, k);
}

// The coordinate along `axis` of a block's lattice points with index t along it (latticePoint's
// bits: the other indices do not change it).
float alongAxis(const solver::FluidLattice& l, float dx, int axis, int t) {
  int c[3] = {0, 0, 0};
  c[axis] = t;
  return solver::latticePoint(l, dx, c[0], c[1], c[2])[axis];
}

}  // namespace

StartSlab startSlab(ranks::Halo& halo, const scene::Scene& scene, const solver::Boundary& boundary,
                    float restDensity) {
  ranks::Communicator& comm = halo.comm();
  const int rankCount = comm.size(), me = comm.rank(), axis = halo.slabs().axis;
  const float dx = scene.solver.spacing;
  std::vector<solver::FluidLattice> lattices;
  std::vector<std::size_t> planeAt;  // each block's first counter of lattice planes
  std::size_t planes = 0;
  for (const scene::FluidBlock& f : scene.fluids) {
    lattices.push_back(solver::fluidLattice(f, dx));
    planeAt.push_back(planes);
    planes += static_cast<std::size_t>(lattices.back().n[axis]);
  }

  // 1. The points kept per lattice plane, and their bounding box: each rank counts an equal share
  // of every block's planes, then the ranks add up.
  std::vector<std::int64_t> kept(planes, 0);
  std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -lo[0]);
  for (std::size_t b = 0; b < lattices.size(); ++b) {
    const solver::FluidLattice& l = lattices[b];
    const long long n = l.n[axis];
    const int t0 = static_cast<int>(n * me / rankCount),
              t1 = static_cast<int>(n * (me + 1) / rankCount);
    walk(l, axis, t0, t1, [&](int i, int j, int k) {
      const Vec3 p = solver::latticePoint(l, dx, i, j, k);
      if (!solver::keepsStartPoint(scene.fluids[b], boundary, p, dx)) return;
      const int t = axis == 0 ? i : axis == 1 ? j : k;
      ++kept[planeAt[b] + static_cast<std::size_t>(t)];
      for (int a = 0; a < 3; ++a)
        lo[a] = std::min(lo[a], double(p[a])), hi[a] = std::max(hi[a], double(p[a]));
    });
  }
  comm.sumInPlace(kept);
  comm.minInPlace(lo);
  comm.maxInPlace(hi);
  StartSlab out;
  for (std::int64_t c : kept) out.total += static_cast<std::uint64_t>(c);
  if (out.total == 0) return out;

  // 2. The cut the first exchange will make: its cell size (from the bounding box and count of
  // every particle, NeighbourGrid::cellSizeFor) and its histogram of cell planes.
  const float blo[3] = {float(lo[0]), float(lo[1]), float(lo[2])};
  const float bhi[3] = {float(hi[0]), float(hi[1]), float(hi[2])};
  const float cellSize =
      grid::NeighbourGrid::cellSizeFor(blo, bhi, out.total, scene.solver.supportRadius());
  const double inv = 1.0 / static_cast<double>(cellSize);
  const long long p0 = ranks::planeOf(blo[axis], inv), p1 = ranks::planeOf(bhi[axis], inv);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(p1 - p0 + 1), 0);
  for (std::size_t b = 0; b < lattices.size(); ++b)
    for (int t = 0; t < lattices[b].n[axis]; ++t) {
      const std::int64_t c = kept[planeAt[b] + static_cast<std::size_t>(t)];
      if (c > 0)
        counts[static_cast<std::size_t>(ranks::planeOf(alongAxis(lattices[b], dx, axis, t), inv) -
                                        p0)] += c;
    }
  const ranks::Slabs slabs = ranks::Slabs::balance(axis, rankCount, p0, counts);
  halo.startWith(slabs, cellSize);

  // 3. This rank's lattice planes (consecutive: the coordinate grows with the index), generated
  // in initialFluid's order; each particle remembers its unit until the ids are known.
  std::vector<std::size_t> unitAt;  // each block's first unit
  std::size_t units = 0;
  std::vector<std::uint64_t> unitOf;
  for (std::size_t b = 0; b < lattices.size(); ++b) {
    const solver::FluidLattice& l = lattices[b];
    unitAt.push_back(units);
    std::size_t blockUnits = 1;
    for (int a = axis + 1; a < 3; ++a) blockUnits *= static_cast<std::size_t>(l.n[a]);
    units += blockUnits;
    int t0 = 0;
    while (t0 < l.n[axis] && slabs.ownerOf(ranks::planeOf(alongAxis(l, dx, axis, t0), inv)) < me)
      ++t0;
    int t1 = t0;
    while (t1 < l.n[axis] && slabs.ownerOf(ranks::planeOf(alongAxis(l, dx, axis, t1), inv)) == me)
      ++t1;
    walk(l, axis, t0, t1, [&](int i, int j, int k) {
      const Vec3 p = latticePoint(l, dx, i, j, k);
      if (!keepsStartPoint(scene.fluids[b], boundary, p, dx)) return;
      const std::size_t unit = axis == 0 ? std::size_t(k) * l.n[1] + j : axis == 1 ? k : 0;
      out.fluid.append(p, scene.fluids[b].velocity, 0, restDensity);
      unitOf.push_back(unitAt[b] + unit);
    });
  }

  // 4. The ids: the points of the units before (all ranks), of this unit on the ranks below, and
  // this rank's before it in the unit.
  std::vector<std::int64_t> below(units, 0);
  for (std::uint64_t u : unitOf) ++below[u];
  std::vector<std::int64_t> first = below;
  comm.sumInPlace(first);
  comm.exclusiveScanInPlace(below);
  std::int64_t before = 0;
  for (std::size_t u = 0; u < units; ++u) {
    const std::int64_t inUnit = first[u];
    first[u] = before + below[u];
    before += inUnit;
  }
  for (std::size_t i = 0; i < unitOf.size(); ++i)
    out.fluid.id[i] = static_cast<std::uint32_t>(first[unitOf[i]]++);
  return out;
}

}  // namespace sph::run
