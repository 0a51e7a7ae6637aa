// How the fluid moves in a step, chosen once from the scene (solver.model, solver.pressure_solver):
// WCSPH, DFSPH or the paper's particle model. Simulation::step() calls the same stages whatever
// the model (sim/run/Simulation.h); each model fills them with its passes, timed under their
// names in the step's profile.
#pragma once

#include <memory>
#include <vector>

#include "sim/scene/SolverParams.h"
#include "sim/solver/SphPasses.h"
#include "sim/solver/StepContext.h"
#include "sim/solver/StepProfile.h"

namespace sph::solver {

class FluidModel {
 public:
  virtual ~FluidModel() = default;
  // Whether the model sums over neighbours: the fluid is sorted by cell (and a rank of a
  // distributed run receives ghosts) before density(). The particle model does not.
  virtual bool usesNeighbours() const = 0;
  // After the neighbour search: the density (with DFSPH's factor and stored pairs).
  virtual void density(StepContext& c, StepProfile& profile) = 0;
  // Pressure and the other forces: accelerations (WCSPH, the particle model), or velocities
  // made divergence-free and then density-invariant (DFSPH).
  virtual void forces(StepContext& c, StepProfile& profile) = 0;
  // Moves the particles with what forces() left; their largest speed and acceleration after.
  virtual MotionBounds integrate(StepContext& c) = 0;
  // The per-particle fields of the run state that travel with their particle (DFSPH's warm
  // start), for a distributed run's migration; none for the others.
  virtual std::vector<std::vector<float>*> particleState(PressureWarmStart& warmStart) const {
    (void)warmStart;
    return {};
  }
};

std::unique_ptr<FluidModel> makeFluidModel(const scene::SolverParams& solver);

}  // namespace sph::solver
