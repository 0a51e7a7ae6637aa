// WCSPH's walls that hold pressure (solver.wall_pressure "extrapolated"): the boundary particles'
// pressure, from their own summation density, is corrected toward the pressure the fluid around
// them extrapolates to them, slowly enough to keep the walls' energy balance
// (sim/solver/WcsphWalls.cpp says how and why). Internal to the WCSPH passes (FluidModel.cpp).
#pragma once

#include "sim/solver/StepContext.h"

namespace sph::solver {

// After computePressure(): each boundary particle the fluid reaches pushes with its summation
// density's pressure plus the Shepard average of its fluid neighbours' shares
// (warmStart.wallShare), and the shares move toward closing the gap to the extrapolated pressure.
// On K processes the ghosts' p and rho are refreshed first (the walls read the second plane).
void correctWallPressure(StepContext& c);

}  // namespace sph::solver
