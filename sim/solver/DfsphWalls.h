// DFSPH's walls that hold pressure (solver.wall_pressure "extrapolated"): each boundary particle
// the fluid reaches takes a stiffness extrapolated from the fluid around it, and its pairs push
// with it beside the fluid particle's own (sim/solver/DfsphWalls.cpp says how and why). Internal
// to the DFSPH passes (Dfsph.cpp, DfsphPairs.cpp).
#pragma once

#include <vector>

#include "sim/solver/StepContext.h"

namespace sph::solver {

// The boundary particles in some fluid particle's wall pairs this step, their fluid neighbours
// with Shepard weights, and their hydrostatic terms; after computeDfsphDensityAndFactor().
void findWallNeighbours(StepContext& c);
// Before a solve: no stiffness applied yet.
void startWallSolve(StepContext& c);
// Each reached boundary particle's stiffness from the fluid's stiffness applied so far in this
// solve plus its running iteration's (`applied` + `stiffness`, both per fluid particle), with the
// hydrostatic term when `hydrostatic`; writes the change since the last call to walls.change.
void changeWallStiffness(StepContext& c, const std::vector<float>& applied,
                         const std::vector<float>& stiffness, bool hydrostatic);
// After a solve: its stiffness joins the step's total (walls.total).
void finishWallSolve(StepContext& c);
// After both solves: each boundary particle's pressure term p / rho^2 for the observables (the
// wall load, tests/StillTankFloor.h), 0 for those the fluid did not reach.
void storeWallPressure(StepContext& c);

}  // namespace sph::solver
