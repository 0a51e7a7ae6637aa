// Turns a scene description into the numbers and particles a run starts from: the derived
// constants (support radius, particle mass, speed of sound, EOS stiffness), the default domain
// and the initial fluid lattice. Kept apart from the step so tests and tools can inspect them.
#pragma once

#include <cstdint>

#include "sim/Kernels.h"
#include "sim/Particles.h"
#include "sim/Scene.h"

namespace sph {

struct DerivedParams {
  float h = 0;     // m, kernel support radius
  float mass = 0;  // kg, per particle: rho0 spacing^3 (the water a lattice cell holds)
  // Constant that makes the density sum read rho0 on the rest lattice: 1 / (spacing^3 sum_j W)
  // over a full cubic lattice. At support 2 spacings the plain sum is off by ~20%.
  float densityNormalisation = 1;
  // Scale of the pressure force that makes the SPH gradient exact for a linear pressure on the
  // rest lattice (1 / first moment of the spiky gradient there, volumes spacing^3): without it
  // the discrete gradient at support 2 spacings is off by ~20% and a still tank carries ~28%
  // excess pressure. A constant factor keeps the force conservative (of the scaled internal
  // energy).
  float gradientCorrection = 1;
  float speedOfSound = 0;  // m/s
  float viscosity = 0;     // m^2/s, resolved (automatic if the scene left it out)
  float stiffness = 0;     // Tait B (Pa) or linear k (m^2/s^2)
  int boundaryLayers = 0;  // layers of boundary particles behind each wall
  Kernels kernels;
};

// Largest speed (m/s) the scene can produce from its initial state, by energy: the largest
// initial or nozzle speed plus a free fall from the highest fluid or nozzle to the domain floor.
// Used for the automatic speed of sound (10x this keeps density variation near 1%, Monaghan
// 1994).
float expectedMaxSpeed(const Scene& scene);

DerivedParams deriveParams(const Scene& scene);

// Step size (DESIGN.md, "Time"): the CFL condition with the speed of sound, a force condition and
// a viscous condition (Monaghan 1992), bounded by solver.max_time_step; the paper's particle
// model takes max_time_step always. `maxSpeed` (m/s) and `maxAcceleration` (m/s^2) are the
// fluid's now; with both 0 it is the step at rest, the largest the scene ever takes.
float timeStep(const Scene& scene, const DerivedParams& d, float maxSpeed, float maxAcceleration);

// Box holding every fluid block, emitter and bounded solid, grown by 10% (at least 4 support
// radii) on each side and by its own height against gravity, so splashes stay inside.
Aabb defaultDomain(const Scene& scene);

// Fills the fluid blocks on their lattices, skipping points closer than 0.4 spacing to a solid.
// Ids start at 0 in block order.
Particles initialFluid(const Scene& scene, const class Boundary& boundary, float restDensity);

}  // namespace sph
