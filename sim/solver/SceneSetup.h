// Turns a scene description into the numbers and particles a run starts from: the derived
// constants (support radius, particle mass, speed of sound, EOS stiffness), the default domain
// and the initial fluid lattice. Kept apart from the step so tests and tools can inspect them.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/solver/Kernels.h"
#include "sim/Particles.h"
#include "sim/scene/Scene.h"

namespace sph::solver {

struct DerivedParams {
  float h = 0;     // m, kernel support radius
  float mass = 0;  // kg, per particle: rho0 spacing^3 (the water a lattice cell holds)
  // Constant that makes the density sum read rho0 on the rest lattice: 1 / (spacing^3 sum_j W)
  // over a full cubic lattice (sim/solver/LatticeSums.h). At support 2 spacings the plain spiky sum is
  // 24% high, the poly6 sum 1%.
  float densityNormalisation = 1;
  // Scale of the pressure force that makes the SPH gradient exact for a linear pressure on the
  // rest lattice (1 / first moment of the spiky gradient there, volumes spacing^3; LatticeSums.h):
  // without it the discrete gradient at support 2 spacings is 4.4% weak, so a still tank needs
  // 4.6% excess pressure to hold its weight. A constant factor keeps the force conservative (of the
  // scaled internal energy).
  float gradientCorrection = 1;
  // DFSPH: the share of each Jacobi increment the solvers apply (it scales alpha_i,
  // DfsphPairs.cpp). A pass multiplies the error's part of wave vector q by 1 - lambda(q), and the
  // lattice's largest lambda grows with the support (LatticeSums.h): 2.82 at 2 spacings, where the
  // solves are measured, 6.72 at 3, where they diverged within the first step (the still tank
  // at 2.6-4 spacings). Above 2 spacings the share is lambda(2) / lambda(support), so no mode is
  // amplified more than at 2; at 2 and below it is 1.
  float jacobiStep = 1;
  float speedOfSound = 0;              // m/s
  float viscosity = 0;                 // m^2/s, resolved (automatic if the scene left it out)
  float stiffness = 0;                 // Tait B (Pa) or linear k (m^2/s^2)
  int boundaryLayers = 0;              // layers of boundary particles behind each wall
  std::uint64_t maxLostParticles = 0;  // resolved SolverParams::maxLostParticles
  Kernels kernels;
};

// Largest speed (m/s) the scene can produce from its initial state, by energy: the largest
// initial, nozzle or (rain.feed_fluid) rain speed plus a free fall from the highest fluid or
// nozzle to the domain floor.
// Used for the automatic speed of sound (10x this keeps density variation near 1%, Monaghan
// 1994).
float expectedMaxSpeed(const scene::Scene& scene);

// Once per run: a Simulation derives them when it is built and holds them (Simulation::params()).
// Not free (lattice sums; with the automatic max_lost_particles, the particle budget walks the
// scene), and h and the wall layers need none of it: SolverParams::supportRadius(), wallLayers().
DerivedParams deriveParams(const scene::Scene& scene);

// Step size (DESIGN.md, "Time"): the CFL condition with the speed of sound, a force condition and
// a viscous condition (Monaghan 1992), bounded by solver.max_time_step; the paper's particle
// model takes max_time_step always. `maxSpeed` (m/s) and `maxAcceleration` (m/s^2) are the
// fluid's now; with both 0 it is the step at rest, the largest the scene ever takes.
float timeStep(const scene::Scene& scene, const DerivedParams& d, float maxSpeed,
               float maxAcceleration);

// Box holding every fluid block, emitter and bounded solid, grown by 10% (at least 4 support
// radii) on each side and by its own height against gravity, so splashes stay inside.
Aabb defaultDomain(const scene::Scene& scene);

// Fills the fluid blocks on their lattices, skipping points closer than 0.4 spacing to a solid.
// Ids start at 0 in block order.
Particles initialFluid(const scene::Scene& scene, const class Boundary& boundary,
                       float restDensity);

// One fluid block's starting lattice as initialFluid walks it: n[a] points along axis a from the
// corner lo, visited block by block, z slowest, x fastest (the particles' ids count that order).
// A distributed start (sim/run/StartSlab.h) generates parts of it with the same functions.
struct FluidLattice {
  Vec3 lo = Vec3::Zero();
  int n[3] = {0, 0, 0};
};
FluidLattice fluidLattice(const scene::FluidBlock& block, float spacing);
// Point (i, j, k) of a lattice. Out of line, so every caller gets the same bits from one compiled
// instance (an inlined copy could contract the multiply-add differently: a point's cell plane
// must not depend on who computed it).
Vec3 latticePoint(const FluidLattice& lattice, float spacing, int i, int j, int k);
// Whether initialFluid keeps lattice point p of `block` (inside a sphere block, not within 0.4
// spacing of a solid).
bool keepsStartPoint(const scene::FluidBlock& block, const class Boundary& boundary, const Vec3& p,
                     float spacing);

// An upper bound of the fluid particles a scene makes by solver.end_time, from its description
// alone (nothing allocated): every lattice point of each fluid block's box, and per emitter the
// layers it can release between start and min(stop, end_time), or its max_particles, and what
// rain.feed_fluid can add. Particle ids are 0 .. total - 1, so this also bounds the ids.
struct ParticleBudget {
  std::uint64_t blocks = 0;
  std::vector<std::uint64_t> emitters;  // per entry of scene.emitters
  // rain.feed_fluid: a drop lands at most once per output frame (sim/rain/RainFeed.h steps the
  // rain at those ticks) and carries drop_volume / spacing^3 of a particle, so count x frames x
  // that share. A bound, reached only where every drop falls into the water each frame (a
  // `region` over the pool, as scenes/rain_fill.json: 9,300 against 6,918 made).
  std::uint64_t rain = 0;
  std::uint64_t total() const;
};
ParticleBudget particleBudget(const scene::Scene& scene);

// Throws InputError naming the scene key to change when the scene could make a particle id of
// `limit` or more: solver.spacing when the fluid blocks alone reach it, else the largest
// emitter's max_particles. `who` has the limit ("the cdt-cpu collision pass"), for a reason
// ("2^24: its texture stores them as floats").
void requireIdsBelow(const scene::Scene& scene, std::uint64_t limit, const std::string& who,
                     const std::string& reason);

}  // namespace sph::solver
