// What the passes of one step read and write, handed to each pass explicitly (STYLE.md rule 2;
// Box2D's b2StepContext): no pass reaches into a Simulation's members, so a pass can be called,
// tested or reordered on its own, and a new solver (another pressure solver, a rank of a
// distributed run) builds the same context around its own state.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/Boundary.h"
#include "sim/NeighbourGrid.h"
#include "sim/Particles.h"
#include "sim/SceneSetup.h"
#include "sim/SolverParams.h"
#include "sim/dist/Communicator.h"

namespace sph {

// Per boundary particle (Boundary.h: dynamic boundary particles). The part of the density that
// other boundary particles contribute is fixed and computed once; the fluid's part is added each
// step for the particles the fluid can reach; the others keep their last values.
struct BoundaryFields {
  std::vector<float> staticDensity;  // kg/m^3
  std::vector<float> density;        // kg/m^3, this step
  std::vector<float> pressureTerm;   // p / rho^2 (m^5 / (kg s^2)), this step
};

// Per fluid particle, rebuilt every step (not part of the state a resume needs).
struct StepScratch {
  std::vector<std::uint32_t> order, permuteScratch;  // the sort's permutation
  std::vector<float> pressureTerm;                   // p / rho^2 (m^5 / (kg s^2))
  std::vector<float> inverseDensity;                 // 1 / rho (m^3/kg)
  std::vector<float> gradientMoment;                 // K_i, see updateGradientCorrection()
};

struct StepContext {
  float dt = 0;  // s, this step's size
  const SolverParams& solver;
  const DerivedParams& derived;
  const Boundary& boundary;
  Particles& fluid;
  NeighbourGrid& grid;  // the fluid's, rebuilt by sortParticles()
  BoundaryFields& boundaryFields;
  StepScratch& scratch;
  // Scale of the pressure force this step (1 / mean discrete gradient moment); set by the
  // density pass, read by the force pass.
  float& gradientCorrection;
  // A distributed run (sim/dist/Halo.h): 1 for the ghosts among the fluid (they take part in the
  // sums but are another rank's to count), and the ranks to add global sums over. Null alone.
  const std::vector<std::uint8_t>* ghost = nullptr;
  dist::Communicator* ranks = nullptr;
};

}  // namespace sph
