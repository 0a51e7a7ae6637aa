// What the validation tests, the `sphsplat bench` sweeps (bench/sweep/SweepMetrics.cpp) and the
// benches measure on a fluid state, one function each (STYLE.md rule 5c), so a test's threshold
// and a sweep's column are the same number. Plain sums in double over the particles in their
// array order; none of them changes the state.
#pragma once

#include <vector>

#include "sim/solver/Boundary.h"
#include "sim/Particles.h"
#include "sim/scene/SolverParams.h"
#include "sim/Types.h"

namespace sph::run {

// Largest x of the fluid (m): the surge front of a dam break whose column stands against a wall
// at the low-x end (Martin & Moyce 1952; tests/test_dam_break.cpp, the sweeps' surge_front).
// -FLT_MAX for no particles.
float surgeFront(const Particles& fluid);

// Largest particle speed |v| (m/s); 0 for no particles.
float maxSpeed(const Particles& fluid);

// Total linear momentum sum m v (kg m/s), each particle of mass `mass` (kg).
Vec3d momentum(const Particles& fluid, double mass);

// Kinetic energy sum 1/2 m |v|^2 (J).
double kineticEnergy(const Particles& fluid, double mass);

// Potential energy sum m (-x . g - floor) (J) in gravity g (m/s^2), from the reference level
// where -x . g = floor (m^2/s^2).
double potentialEnergy(const Particles& fluid, double mass, const Vec3& gravity, double floor);

// The energy the equation of state stores (J): sum m e(rho), e(rho) = integral of p / rho^2 from
// rho0, with stiffness B (Tait, Pa) or k (linear, m^2/s^2), as DerivedParams::stiffness. Particles
// below rest density store nothing when negative pressure is clamped. The solver scales its
// pressure force by the gradient correction; the energy its forces conserve is this times that.
double elasticEnergy(const Particles& fluid, const scene::SolverParams& solver, double mass,
                     double stiffness);

// Mean pressure p (Pa) and height y (m) of the particles below height `top` (m): the bottom
// layer of a still tank, whose pressure should be rho0 g (surface - height) (tests/
// test_still_tank.cpp, test_dfsph.cpp). All zero for no such particle.
struct LayerMean {
  double pressure = 0;
  double height = 0;
  std::size_t count = 0;
};
LayerMean bottomLayer(const Particles& fluid, double top);

// The force (N) the fluid's pressure exerts on the boundary particles inside `sensor`: what a
// load cell behind that part of the wall reads, so its normal component over the part's area is
// the pressure a sensor flush with the wall measures. The pair is the pressure term of both
// solvers: c m^2 (p_i/rho_i^2 + p_b/rho_b^2) |gradW_spiky(x_i - x_b)| pushing fluid particle i
// away from boundary particle b and b away from i (SphPasses.cpp, computeForces()), with
// `boundaryPressureTerm` p_b/rho_b^2 (Simulation::boundaryPressureTerm(): WCSPH's wall pressure,
// zeros for DFSPH, whose walls push with k_i alone, the p_i/rho_i^2 term of its output p;
// Dfsph.cpp) and c the step's gradient correction (Simulation::gradientCorrection()). Read after a
// step, the fluid has moved by dt v since its p was computed: at rest, a small part of a spacing.
Vec3d wallLoad(const Particles& fluid, const solver::BoundaryParticles& boundary,
               const std::vector<float>& boundaryPressureTerm, const Aabb& sensor, double mass,
               double h, double gradientCorrection);

// Mean height (m) of the water's free surface over the x-z rectangle of `columns`, at the
// centres of an n x n grid of vertical lines across it: on each, where the fill fraction
// phi(p) = sum_j W(|p - x_j|) / L falls to 1/2 (poly6 W of support `h`; L its sum over the rest
// lattice of spacing `dx`, so phi = 1 inside water at rest and, for a flat rest lattice, 1/2 half
// a spacing above its top layer: where that water's cells end). Found by bisection between
// columns.lo.y (in the water) and columns.hi.y (above it); a line with no water reads lo.y. The
// rising pool of rain.feed_fluid (tests/test_rain_feed.cpp, docs/benchmarks.md).
double waterLevel(const Particles& fluid, const Aabb& columns, float h, float dx, int n = 8);

// Deviation of the density from rest density rho0 (kg/m^3), as fractions of rho0.
struct DensityError {
  double meanCompression = 0;  // mean of max(0, (rho - rho0) / rho0): the pressure solve's error
                               // (free-surface particles lack neighbours and read low; not counted)
  double maxCompression = 0;   // its largest value
  double meanDeviation = 0;    // mean of |rho - rho0| / rho0 (a fluid at rest: both signs count)
  double meanDensity = 0;      // kg/m^3
  double maxDensity = 0;       // kg/m^3
};
// All zero for no particles.
DensityError densityError(const Particles& fluid, double restDensity);

}  // namespace sph::run
