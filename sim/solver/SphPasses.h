// The passes of an SPH step (DESIGN.md, "The SPH stage"), each a function of the step's context
// (sim/solver/StepContext.h). Simulation::step() calls them in order and times each one (StepProfile).
// The neighbour passes are built with -ffast-math (SphPasses.cpp says what keeps them
// bit-reproducible); the element-wise ones are not (EquationOfState.cpp, Integration.cpp).
#pragma once

#include <cstdint>

#include "sim/solver/StepContext.h"
#include "sim/Types.h"

namespace sph::solver {

// Setup, once per run: the boundary-boundary part of each boundary particle's density.
void computeStaticBoundaryDensity(StepContext& c);

// Counting sort of the fluid by grid cell (cell = h); every field permuted by Particles::permute.
void sortParticles(StepContext& c);
// rho_i = sum_j m W(x_i - x_j) over fluid and boundary neighbours (seed 003, eq. (1)), the
// boundary particles' densities, and the gradient correction of the force pass.
void computeDensity(StepContext& c);
// c.gradientCorrection from the particles' gradient moments (scratch.gradientMoment), after a
// density pass that computed them.
void updateGradientCorrection(StepContext& c);
// Equation of state for fluid and boundary particles (the walls that hold the extrapolated
// pressure get theirs from correctWallPressure()), and the force pass's per-particle factors.
void computePressure(StepContext& c);
// The scene's equation of state at density rho (kg/m^3): p (Pa), clamped as computePressure()'s.
float equationOfState(const StepContext& c, float rho);
// Pressure (spiky gradient), viscosity (Müller 2003), no-slip walls and gravity.
void computeForces(StepContext& c);
// DFSPH (sim/solver/Dfsph.cpp, sim/solver/DfsphPairs.cpp; Bender & Koschier 2015, 2017), in step order after
// sortParticles(): the density, the per-particle factor and the stored pairs (the step's one
// neighbour search), the divergence-free solver on the step's initial velocities, the non-pressure
// forces over the pairs, predictVelocity(), the constant-density solver, then
// integratePositions().
void computeDfsphDensityAndFactor(StepContext& c);
void solveDivergence(StepContext& c);
// Viscosity, no-slip walls and gravity into a (computeForces() without the pressure terms).
void computeDfsphViscosity(StepContext& c);
// v += dt a.
void predictVelocity(StepContext& c);
void solveDensity(StepContext& c);
// The paper's particle model (seed 000): gravity only, no neighbour passes.
void applyGravityOnly(StepContext& c);

// Largest speed and acceleration after an integration, for the next step size.
struct MotionBounds {
  float maxSpeed = 0;         // m/s
  float maxAcceleration = 0;  // m/s^2
};
// The fluid's largest speed and acceleration now.
MotionBounds motionBounds(const Particles& f);
// Symplectic Euler: velocities first, then positions with the new velocities.
MotionBounds integrate(StepContext& c);
// x += dt v with the velocities the DFSPH solvers left (a holds the step's acceleration).
MotionBounds integratePositions(StepContext& c);
// Puts back every particle whose path of this step entered a solid (Solid.h, the safety net).
void enforceBoundaries(StepContext& c);
// The guard: a non-finite state throws StabilityError naming the step, the time and the particle
// with the lowest id at fault. Particles outside `domain` are removed (with their warm start) and
// their number returned, unless that brings the run's losses (`lostBefore` + these) past
// `maxLost`: then it throws too, naming the lowest id among them.
std::uint64_t checkStability(StepContext& c, const Aabb& domain, std::uint64_t step, double time,
                             std::uint64_t lostBefore, std::uint64_t maxLost);

}  // namespace sph::solver
