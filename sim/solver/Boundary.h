// Static walls and containers (DESIGN.md, "Boundaries"): each shape is sampled once with boundary
// particles that take part in density and pressure like fluid neighbours (after Akinci et al.
// 2012), laid out on the continuation of the fluid lattice: `layers` layers behind the wall
// surface at spacing dx, the first at dx/2, so a fluid particle resting at dx/2 in front of a flat
// wall sees the same neighbourhood as one inside the fluid. Boundary particles carry the fluid
// particle mass and, every step, get a density and a pressure of their own (the dynamic boundary
// particles of Crespo et al. 2007, with summation density): the wall then pushes back with the
// symmetric pressure force, which keeps the hydrostatic balance at the wall and, being the
// gradient of the boundary's share of the internal energy, conserves energy. That is WCSPH's wall
// with solver.wall_pressure "summation"; by default its pressure is also corrected slowly toward
// the one the fluid extrapolates to it (sim/solver/WcsphWalls.cpp). DFSPH's boundary particles
// take a stiffness extrapolated from the fluid instead (sim/solver/DfsphWalls.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/grid/NeighbourGrid.h"
#include "sim/scene/Scene.h"
#include "sim/scene/Solid.h"

namespace sph::solver {

struct BoundaryParticles {
  std::vector<float> x, y, z;  // m, sorted by cell of the boundary grid
  std::size_t size() const { return x.size(); }
};

class Boundary {
 public:
  Boundary() = default;
  // Samples every shape (clipped to the domain grown by the support radius, where nothing can
  // reach them), then bins the samples into a grid of cell size h once for the whole run.
  Boundary(const std::vector<scene::BoundaryShape>& shapes, const Aabb& domain, float spacing,
           int layers, float supportRadius);

  const BoundaryParticles& particles() const { return particles_; }
  const grid::NeighbourGrid& grid() const { return grid_; }
  const std::vector<scene::Solid>& solids() const { return solids_; }

  // Smallest signed distance from p to any solid (m); +inf without solids.
  float distance(const Vec3& p) const;
  // Applies keepOutside() for every solid; returns true if the particle was moved.
  bool enforce(const Vec3& xOld, Vec3& xNew, Vec3& v) const;

 private:
  BoundaryParticles particles_;
  grid::NeighbourGrid grid_;
  std::vector<scene::Solid> solids_;
  float spacing_ = 0;
  int layers_ = 0;
};

// How many points sampleBoundaryShape() returns for these arguments (the plane: an upper bound),
// computed without generating them: the memory estimate's count (sim/run/MemoryEstimate.h), in
// double because a scene too big for the machine is exactly what it must describe.
double countBoundarySamples(const scene::BoundaryShape& shape, const Aabb& domain, float spacing,
                            int layers);
// Samples of one shape (exposed for tests): positions on the lattice continuation described above.
std::vector<Vec3> sampleBoundaryShape(const scene::BoundaryShape& shape, const Aabb& domain,
                                      float spacing, int layers);

}  // namespace sph::solver
