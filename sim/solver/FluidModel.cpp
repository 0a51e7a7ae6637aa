#include "sim/solver/FluidModel.h"

#include "sim/Assert.h"
#include "sim/solver/DfsphWalls.h"
#include "sim/solver/Validate.h"
#include "sim/solver/WcsphWalls.h"

namespace sph::solver {
namespace {

void checkDensityPass(const StepContext& c) {
  validate("the density pass",
           [&] { return checkDensity(c.fluid, c.derived, c.solver.densityKernel); });
}

// Weakly compressible SPH: density, the equation of state (and the walls' correction toward the
// extrapolated pressure, WcsphWalls.cpp), forces, symplectic Euler.
class Wcsph final : public FluidModel {
 public:
  explicit Wcsph(bool wallsHoldPressure) : wallsHoldPressure_(wallsHoldPressure) {}
  bool usesNeighbours() const override { return true; }
  void density(StepContext& c, StepProfile& profile) override {
    timed(profile, Pass::Density, [&] { computeDensity(c); });
    checkDensityPass(c);
  }
  void forces(StepContext& c, StepProfile& profile) override {
    timed(profile, Pass::Pressure, [&] {
      computePressure(c);
      if (wallsHoldPressure_) correctWallPressure(c);
    });
    timed(profile, Pass::Forces, [&] { computeForces(c); });
  }
  MotionBounds integrate(StepContext& c) override { return solver::integrate(c); }
  std::vector<std::vector<float>*> particleState(PressureWarmStart& warmStart) const override {
    if (!wallsHoldPressure_) return {};
    return {&warmStart.wallShare};
  }

 private:
  bool wallsHoldPressure_;
};

// Divergence-free SPH (sim/solver/Dfsph.cpp): the density, factor and pairs from one neighbour
// search, the divergence-free solver, the other forces, the constant-density solver.
class Dfsph final : public FluidModel {
 public:
  bool usesNeighbours() const override { return true; }
  void density(StepContext& c, StepProfile& profile) override {
    timed(profile, Pass::Factor, [&] {
      computeDfsphDensityAndFactor(c);
      if (c.solver.wallPressure == scene::WallPressure::Extrapolated) findWallNeighbours(c);
    });
    checkDensityPass(c);
  }
  void forces(StepContext& c, StepProfile& profile) override {
    timed(profile, Pass::Divergence, [&] { solveDivergence(c); });
    timed(profile, Pass::Forces, [&] { computeDfsphViscosity(c), predictVelocity(c); });
    timed(profile, Pass::Pressure, [&] { solveDensity(c); });
  }
  MotionBounds integrate(StepContext& c) override { return integratePositions(c); }
  std::vector<std::vector<float>*> particleState(PressureWarmStart& warmStart) const override {
    return {&warmStart.density, &warmStart.divergence};
  }
};

// The paper's particle model (seed 000): gravity only, no neighbour passes.
class GravityOnly final : public FluidModel {
 public:
  bool usesNeighbours() const override { return false; }
  void density(StepContext&, StepProfile&) override {}
  void forces(StepContext& c, StepProfile& profile) override {
    timed(profile, Pass::Forces, [&] { applyGravityOnly(c); });
  }
  MotionBounds integrate(StepContext& c) override { return solver::integrate(c); }
};

}  // namespace

std::unique_ptr<FluidModel> makeFluidModel(const scene::SolverParams& solver) {
  if (solver.model != scene::SolverModel::Sph) return std::make_unique<GravityOnly>();
  if (solver.pressure == scene::PressureSolver::Dfsph) return std::make_unique<Dfsph>();
  return std::make_unique<Wcsph>(solver.wallPressure == scene::WallPressure::Extrapolated);
}

}  // namespace sph::solver
