// A distributed start (docs/scaling.md, "A distributed start"): each rank generates only its
// slab's part of the scene's starting fluid, so no rank ever holds (or builds) the whole of it.
//
// The fluid blocks are lattices, and a lattice point's coordinate along the slab axis depends on
// its index along that axis alone, so the cut is found before any particle is stored: each rank
// counts the points initialFluid keeps in an equal share of every block's lattice planes (and
// their bounding box); one sum (and a min and a max) over the ranks gives every rank the count of
// each lattice plane, from which it derives the cell size and the per-cell-plane histogram that
// the first Halo::exchange() will find, and so that exchange's cut (nothing migrates at the first
// step). Each rank then generates the lattice planes of its slab, in initialFluid's order.
//
// A particle's id (and its key, its place in the starting order) is the number of points kept
// before it in initialFluid's order. Within a "unit" (the lattice points of one block that share
// the coordinates above the slab axis: a row along x when the slabs cut x, a z plane when they cut
// y, the whole block when they cut z) the ranks' points come in rank order, so
//   id = (points of the units before, all ranks) + (points of its unit on the ranks below)
//        + (its index among this rank's points of the unit):
// one sum and one exclusive scan of a counter per unit.
#pragma once

#include <cstdint>

#include "sim/Particles.h"
#include "sim/scene/Scene.h"
#include "sim/ranks/Halo.h"

namespace sph::solver {
class Boundary;
}

namespace sph::run {

struct StartSlab {
  Particles fluid;          // this rank's particles, in the single-process order
  std::uint64_t total = 0;  // particles on all ranks
};

// Collective. Sets `halo`'s first cut (Halo::startWith) and returns this rank's part of
// initialFluid(scene, boundary, restDensity), ids as the single process gives them.
StartSlab startSlab(ranks::Halo& halo, const scene::Scene& scene, const solver::Boundary& boundary,
                    float restDensity);

}  // namespace sph::run
