#include "sim/Simulation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/Assert.h"
#include "sim/SphPasses.h"
#include "sim/Validate.h"

namespace sph {

Simulation::Simulation(const Scene& scene)
    : scene_(scene),
      derived_(deriveParams(scene)),
      boundary_(scene.boundaries, scene.domain, scene.solver.spacing, derived_.boundaryLayers,
                derived_.h) {
  gradientCorrection_ = derived_.gradientCorrection;
  StepContext setup = context(0);
  computeStaticBoundaryDensity(setup);
  fluid_ = initialFluid(scene_, boundary_, scene_.solver.restDensity);
  state_.nextId = static_cast<std::uint32_t>(fluid_.size());
  for (const EmitterDesc& e : scene_.emitters) emitters_.emplace_back(e, scene_.solver.spacing);
  state_.maxAcceleration = scene_.solver.gravity.norm();
  for (std::size_t i = 0; i < fluid_.size(); ++i) {
    state_.maxSpeed = std::max(state_.maxSpeed, fluid_.velocity(i).norm());
  }
}

Simulation::~Simulation() = default;

void Simulation::setCollisionPass(std::unique_ptr<CollisionPass> pass) {
  collision_ = std::move(pass);
}

float Simulation::nextTimeStep() const {
  return chooseTimeStep();
}

// Step size: sim/SceneSetup.h, timeStep().
float Simulation::chooseTimeStep() const {
  return timeStep(scene_, derived_, state_.maxSpeed, state_.maxAcceleration);
}

StepContext Simulation::context(float dt) {
  return StepContext{dt,         scene_.solver,   derived_, boundary_,           fluid_,
                     grid_,      boundaryFields_, scratch_, gradientCorrection_, state_.warmStart,
                     solveStats_};
}

void Simulation::step(double limit) {
  double dt = chooseTimeStep();
  if (state_.time + dt > limit) dt = limit - state_.time;
  // Avoid a sliver step right before the limit: split the remainder into two equal steps.
  else if (state_.time + 1.5 * dt > limit)
    dt = 0.5 * (limit - state_.time);
  StepContext c = context(static_cast<float>(dt));
  auto timed = [&](Pass pass, auto&& run) {
    PassTimer t(profile_, pass);
    run();
  };
  timed(Pass::Emit, [&] { emitParticles(dt); });
  // The paper's particle model has no neighbour passes, so nothing to sort for.
  const bool sph = scene_.solver.model == SolverModel::Sph;
  const bool dfsph = sph && scene_.solver.pressure == PressureSolver::Dfsph;
  if (sph) {
    timed(Pass::Sort, [&] { sortParticles(c); });
    timed(Pass::Density, [&] { computeDensity(c); });
    validate("the density pass",
             [&] { return checkDensity(fluid_, derived_, scene_.solver.densityKernel); });
  }
  if (dfsph) {  // sim/Dfsph.cpp
    timed(Pass::Factor, [&] { computeDfsphFactor(c); });
    timed(Pass::Divergence, [&] { solveDivergence(c); });
    timed(Pass::Forces, [&] { clearPressure(c), computeForces(c), predictVelocity(c); });
    timed(Pass::Pressure, [&] { solveDensity(c); });
  } else if (sph) {
    timed(Pass::Pressure, [&] { computePressure(c); });
    timed(Pass::Forces, [&] { computeForces(c); });
  } else {
    timed(Pass::Forces, [&] { applyGravityOnly(c); });
  }
  timed(Pass::Integrate, [&] {
    const MotionBounds bounds = dfsph ? integratePositions(c) : integrate(c);
    state_.maxSpeed = bounds.maxSpeed, state_.maxAcceleration = bounds.maxAcceleration;
  });
  state_.time += dt;
  state_.step += 1;
  state_.lastDt = c.dt;
  timed(Pass::Collide, [&] { collide(c.dt); });
  timed(Pass::Boundaries, [&] { enforceBoundaries(c); });
  timed(Pass::Guard, [&] {
    const std::uint64_t lost = checkStability(c, scene_.domain, state_.step, state_.time,
                                              state_.lostParticles, derived_.maxLostParticles);
    state_.lostParticles += lost;
    if (lost == 0) return;
    // The next step's size follows the particles that stayed.
    const MotionBounds bounds = motionBounds(fluid_);
    state_.maxSpeed = bounds.maxSpeed, state_.maxAcceleration = bounds.maxAcceleration;
  });
  validate("the step", [&] { return checkState(fluid_, state_.nextId); });
  profile_.steps += 1;
  profile_.particleSteps += fluid_.size();
}

void Simulation::advanceTo(double t) {
  while (state_.time < t) step(t);
}

void Simulation::emitParticles(double dt) {
  const double end = state_.time + dt;
  for (std::size_t e = 0; e < emitters_.size(); ++e) {
    emitters_[e].emit(end, dt, fluid_, state_.nextId, scene_.solver.restDensity);
  }
}

void Simulation::collide(float dt) {
  if (!collision_) return;
  CollisionContext context;
  context.time = state_.time;
  context.dt = dt;
  context.step = state_.step;
  collision_->apply(fluid_, context);
}

RunState Simulation::runState() const {
  RunState s = state_;
  s.emitters.clear();
  for (const Emitter& e : emitters_) s.emitters.push_back(e.state());
  return s;
}

void Simulation::restore(const RunState& state, Particles fluid) {
  state_ = state;
  fluid_ = std::move(fluid);
  for (std::size_t e = 0; e < emitters_.size() && e < state.emitters.size(); ++e) {
    emitters_[e].setState(state.emitters[e]);
  }
  state_.emitters.clear();
}

}  // namespace sph
