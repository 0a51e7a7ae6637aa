// What the passes of one step read and write, handed to each pass explicitly (STYLE.md rule 2;
// Box2D's b2StepContext): no pass reaches into a Simulation's members, so a pass can be called,
// tested or reordered on its own, and a new solver (another pressure solver, a rank of a
// distributed run) builds the same context around its own state.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sim/solver/Boundary.h"
#include "sim/grid/CellBatch.h"
#include "sim/grid/NeighbourGrid.h"
#include "sim/grid/PairStore.h"
#include "sim/Particles.h"
#include "sim/solver/SceneSetup.h"
#include "sim/scene/SolverParams.h"
#include "sim/ranks/Communicator.h"

namespace sph::ranks {
class Halo;
}

namespace sph::solver {

// Per boundary particle (Boundary.h: dynamic boundary particles). The part of the density that
// other boundary particles contribute is fixed and computed once; the fluid's part is added each
// step for the particles the fluid can reach; the others keep their last values.
struct BoundaryFields {
  std::vector<float> staticDensity;  // kg/m^3
  std::vector<float> density;        // kg/m^3, this step
  std::vector<float> pressureTerm;   // p / rho^2 (m^5 / (kg s^2)), this step
  // WCSPH's walls that hold pressure (sim/solver/WcsphWalls.cpp), this step: the pressure the
  // fluid extrapolates to the particle less the one it pushes with (Pa), and how much fluid is
  // within reach, sum_f W_bf / W(0) (0 where none is, and the residual means nothing).
  std::vector<float> wallResidual;
  std::vector<float> wallReach;
};

// Per fluid particle, rebuilt every step (not part of the state a resume needs).
struct StepScratch {
  std::vector<std::uint32_t> order, permuteScratch;  // the sort's permutation
  std::vector<float> pressureTerm;                   // p / rho^2 (m^5 / (kg s^2))
  std::vector<float> inverseDensity;                 // 1 / rho (m^3/kg)
  std::vector<float> gradientMoment;                 // K_i, see updateGradientCorrection()
  // DFSPH (sim/solver/Dfsph.cpp): G_i = sum_j V_j gradW_ij over fluid and boundary (1/m, 3 arrays), the
  // factor alpha_i = 1 / (|G_i|^2 + sum_fluid |V_j gradW_ij|^2) (m^2), the source term of the
  // running solve and the stiffness of its last iteration (m^2/s^2).
  std::vector<float> gradientSumX, gradientSumY, gradientSumZ;
  std::vector<float> factor, source, stiffness;
  std::vector<float> solveStart;  // each particle's warm start of the running solve (m^2/s^2)
  // Each particle's velocity as {0, vx, vy, vz} (m/s), packed for DFSPH's source passes.
  std::vector<std::array<float, 4>> packedVelocity;
  // sum over boundary neighbours of h - r (m): the no-slip wall drag of computeDfsphViscosity().
  std::vector<float> wallWeight;
  // DFSPH's fluid pairs, found once a step by computeDfsphDensityAndFactor() and read by every
  // solver iteration: for each row of grid cells (rowRange(), a contiguous range of particles), the
  // neighbours j of its particles in particle order, each with V_j gradW_ij (1/m) and h - r_ij
  // (m, the viscosity's Laplacian, computeDfsphViscosity()); pairCount[i]
  // of them belong to particle i (i itself excluded). Rows start on a cache line, so a
  // particle's pairs have the same alignment whichever thread built or reads them (PairStore.h).
  grid::PairStore pairs;
  std::vector<std::uint32_t> pairCount;
  std::vector<float> indexBits;  // i's bits as a float: carries indices through the batches
  // DFSPH's walls that hold pressure (sim/solver/DfsphWalls.cpp): each fluid particle's boundary
  // pairs, stored as the fluid pairs are (index b, V_b gradW_ib, h - r), wallPairCount[i] of
  // them; empty with solver.wall_pressure "none".
  grid::PairStore wallPairs;
  std::vector<std::uint32_t> wallPairCount;
};

// DFSPH's boundary particles within reach of the fluid this step and the pressure they carry
// (sim/solver/DfsphWalls.cpp): each takes the Shepard average of its fluid neighbours' stiffness
// and the hydrostatic term.
struct WallStiffness {
  std::vector<float> indexBits;            // per boundary particle: b's bits as a float
  std::vector<std::uint32_t> cursor;       // per boundary particle: findWallNeighbours()'s sort
  std::vector<std::uint32_t> active;       // the boundary particles reached, ascending
  std::vector<std::uint32_t> start;        // per active particle: its neighbours' first index
  std::vector<std::uint32_t> neighbour;    // fluid neighbours of the active particles
  std::vector<float> weight;               // W_bf / sum_f W_bf
  std::vector<float> hydrostatic;          // per active: g . sum_f w_bf (x_b - x_f) (m^2/s^2)
  std::vector<float> applied;              // per active: stiffness the running solve applied
  std::vector<float> total;                // per active: both solves' stiffness this step
  std::vector<float> change;               // per boundary particle: this iteration's change
};

// Per fluid particle, in the fluid's order, what the pressure solver carries from one step to the
// next. Part of what a resume needs (RunState); each empty where the solver has none.
struct PressureWarmStart {
  // DFSPH's warm start (Bender & Koschier 2017, sec. 4.3): the sum of each solver's stiffness
  // values over the last step (m^2/s^2, a pressure over a density).
  std::vector<float> density;     // constant-density solver
  std::vector<float> divergence;  // divergence-free solver
  // WCSPH's walls that hold pressure (sim/solver/WcsphWalls.cpp): the particle's share of its
  // walls' pressure correction (Pa).
  std::vector<float> wallShare;

  // Every array, for the code that moves, removes or stores them all alike.
  std::array<std::vector<float>*, 3> fields() { return {&density, &divergence, &wallShare}; }
};

// What the DFSPH solvers did: the last step's iterations and the errors they stopped at
// (percent, as the scene's max_density_error / max_divergence_error), and the run's totals.
struct PressureSolveStats {
  int densityIterations = 0, divergenceIterations = 0;
  float densityError = 0, divergenceError = 0;  // %
  std::uint64_t totalDensityIterations = 0, totalDivergenceIterations = 0;
  std::uint64_t steps = 0;
};

struct StepContext {
  float dt = 0;  // s, this step's size
  const scene::SolverParams& solver;
  const DerivedParams& derived;
  const Boundary& boundary;
  Particles& fluid;
  grid::NeighbourGrid& grid;  // the fluid's, rebuilt by sortParticles()
  BoundaryFields& boundaryFields;
  StepScratch& scratch;
  WallStiffness& walls;  // DFSPH with solver.wall_pressure "extrapolated"
  // Scale of the pressure force this step (1 / mean discrete gradient moment); set by the
  // density pass, read by the force pass.
  float& gradientCorrection;
  PressureWarmStart& warmStart;  // DFSPH only
  PressureSolveStats& solveStats;
  // A distributed run (sim/ranks/Halo.h): 1 for the ghosts among the fluid (they take part in the
  // sums but are another rank's to count), and the ranks to add global sums over. Null alone.
  const std::vector<std::uint8_t>* ghost = nullptr;
  ranks::Communicator* ranks = nullptr;
  // The same run's decomposition: DFSPH's iterations refresh the ghosts' velocities through it.
  ranks::Halo* halo = nullptr;
};

}  // namespace sph::solver
