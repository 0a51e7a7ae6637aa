#include "sim/run/Simulation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "sim/Assert.h"
#include "sim/rain/RainFeed.h"
#include "sim/ranks/Halo.h"
#include "sim/run/StartSlab.h"
#include "sim/solver/SphPasses.h"
#include "sim/solver/Validate.h"

namespace sph::run {

Simulation::Simulation(const scene::Scene& scene) : Simulation(scene, nullptr, Start::Slab) {}

Simulation::Simulation(const scene::Scene& scene, ranks::Halo& start, Start what)
    : Simulation(scene, &start, what) {}

Simulation::Simulation(const scene::Scene& scene, ranks::Halo* start, Start what)
    : scene_(scene),
      derived_(solver::deriveParams(scene)),
      boundary_(scene.boundaries, scene.domain, scene.solver.spacing, derived_.boundaryLayers,
                derived_.h),
      model_(solver::makeFluidModel(scene.solver)),
      decomposition_(wholeFluid()) {
  setUp(start, what);
}

void Simulation::setUp(ranks::Halo* start, Start what) {
  gradientCorrection_ = derived_.gradientCorrection;
  solver::StepContext setup = context(0);
  computeStaticBoundaryDensity(setup);
  if (start && what == Start::Empty) {
    // A resume: restore() brings the fluid, its ids and the run state.
  } else if (start) {
    run::StartSlab slab = run::startSlab(*start, scene_, boundary_, scene_.solver.restDensity);
    fluid_ = std::move(slab.fluid);
    state_.nextId = static_cast<std::uint32_t>(slab.total);
    startKeys_.assign(fluid_.id.begin(), fluid_.id.end());
  } else {
    fluid_ = initialFluid(scene_, boundary_, scene_.solver.restDensity);
    state_.nextId = static_cast<std::uint32_t>(fluid_.size());
  }
  for (const scene::EmitterDesc& e : scene_.emitters)
    emitters_.emplace_back(e, scene_.solver.spacing, derived_.h);
  state_.maxAcceleration = scene_.solver.gravity.norm();
  for (std::size_t i = 0; i < fluid_.size(); ++i) {
    state_.maxSpeed = std::max(state_.maxSpeed, fluid_.velocity(i).norm());
  }
  if (start) start->maxOverRanks(state_.maxSpeed, state_.maxAcceleration);  // exact maxima
  feed_ = fluidFeed(scene_);
}

Simulation::~Simulation() = default;

void Simulation::setCollisionPass(std::unique_ptr<CollisionPass> pass) {
  collision_ = std::move(pass);
}

float Simulation::nextTimeStep() const {
  return chooseTimeStep();
}

// Step size: sim/solver/SceneSetup.h, timeStep().
float Simulation::chooseTimeStep() const {
  return timeStep(scene_, derived_, state_.maxSpeed, state_.maxAcceleration);
}

solver::StepContext Simulation::context(float dt) {
  solver::StepContext c{
      dt,      scene_.solver,       derived_,         boundary_,  fluid_, grid_, boundaryFields_,
      scratch_, walls_, gradientCorrection_, state_.warmStart, solveStats_};
  decomposition_->share(c);
  return c;
}

std::vector<std::vector<float>*> Simulation::particleState(solver::PressureWarmStart& w) const {
  return model_->particleState(w);
}

void Simulation::setHalo(ranks::Halo* halo) {
  halo_ = halo;
  decomposition_ = halo ? haloSlab(*halo) : wholeFluid();
  if (!halo_) return;
  // The particles' places in the starting order (a slab start's ids, a resumed slab's indices in
  // the frame), or none: a whole fluid is in that order from 0.
  halo_->adopt(fluid_, std::move(startKeys_));
  startKeys_.clear();
  // Run state per particle (DFSPH's warm start) moves with its particle (docs/scaling.md).
  for (std::vector<float>* field : model_->particleState(state_.warmStart)) halo_->attach(*field);
}

double Simulation::stepSize(double limit) const {
  double dt = chooseTimeStep();
  if (state_.time + dt > limit) dt = limit - state_.time;
  // Avoid a sliver step right before the limit: split the remainder into two equal steps.
  else if (state_.time + 1.5 * dt > limit)
    dt = 0.5 * (limit - state_.time);
  return dt;
}

void Simulation::step(double limit) {
  // A feed (the rain that lands in the water) acts at its ticks: the step lands on the next one.
  const double tick = settling_ ? limit : feed_->nextTick(state_.time);
  const double dt = stepSize(std::min(limit, tick));
  solver::StepContext c = context(static_cast<float>(dt));
  const bool neighbours = model_->usesNeighbours();
  using solver::Pass, solver::timed;

  if (!settling_) timed(profile_, Pass::Emit, [&] { emitParticles(dt); });
  decomposition_->findNeighbours(c, profile_, neighbours);  // Sort (and Exchange)
  model_->density(c, profile_);                             // Density or Factor
  model_->forces(c, profile_);  // Pressure, Forces (and DFSPH's Divergence)
  decomposition_->afterForces(fluid_, profile_, neighbours);  // Exchange
  // The pipe's end holds against the pressure; gravity-only particles feel none.
  if (neighbours && !settling_) {
    timed(profile_, Pass::Emit, [&] {
      for (const Emitter& e : emitters_) e.guide(fluid_);
    });
  }
  timed(profile_, Pass::Integrate, [&] {
    const solver::MotionBounds bounds = model_->integrate(c);
    state_.maxSpeed = bounds.maxSpeed, state_.maxAcceleration = bounds.maxAcceleration;
    decomposition_->agreeOnMotion(state_.maxSpeed, state_.maxAcceleration);
  });
  state_.time += dt;
  state_.step += 1;
  state_.lastDt = c.dt;
  if (!settling_) timed(profile_, Pass::Collide, [&] { collide(c.dt); });
  timed(profile_, Pass::Boundaries, [&] { enforceBoundaries(c); });
  timed(profile_, Pass::Guard,
        [&] { decomposition_->guard(c, scene_, derived_.maxLostParticles, state_); });
  if (!settling_ && state_.time >= tick) {
    timed(profile_, Pass::Emit, [&] { feed_->feed(tick, fluid_, state_); });
    // The landed water's particles start the solver's state from 0, as emitted ones do at the
    // sort: a frame written now holds the state of every particle.
    for (std::vector<float>* v : state_.warmStart.fields()) {
      if (!v->empty()) v->resize(fluid_.size(), 0.0f);
    }
  }
  validate("the step", [&] { return solver::checkState(fluid_, state_.nextId); });
  profile_.steps += 1;
  profile_.particleSteps += fluid_.size();
}

void Simulation::advanceTo(double t) {
  while (state_.time < t) step(t);
}

bool Simulation::settle(double seconds, const std::function<void(const Simulation&)>& afterStep,
                        const std::function<bool()>& stop) {
  settling_ = true;
  struct Done {
    bool& flag;
    ~Done() { flag = false; }
  } done{settling_};  // a blow-up leaves the simulation as it was, settling or not
  while (state_.time < seconds) {
    if (stop && stop()) return false;
    step(seconds);
    if (afterStep) afterStep(*this);
  }
  state_.time = 0;
  state_.step = 0;
  profile_ = solver::StepProfile{};
  solveStats_ = solver::PressureSolveStats{};
  return true;
}

void Simulation::emitParticles(double dt) {
  const double end = state_.time + dt;
  for (std::size_t e = 0; e < emitters_.size(); ++e) {
    // Distributed: the rank holding the nozzle releases the particles; the others advance the
    // emitter's state and the ids alike.
    Particles& into =
        decomposition_->owns(scene_.emitters[e].position) ? fluid_ : emittedElsewhere_;
    emitters_[e].emit(end, dt, into, state_.nextId, scene_.solver.restDensity);
  }
  emittedElsewhere_.clear();
}

void Simulation::restoreRain(double time, const std::vector<Vec3>& positions,
                             const std::vector<std::uint32_t>& generations) {
  if (rain::RainFeed* rain = feed_->rain()) rain->restore(time, positions, generations);
}

void Simulation::collide(float dt) {
  if (!collision_) return;
  CollisionContext context;
  context.time = state_.time;
  context.dt = dt;
  context.step = state_.step;
  decomposition_->collide(*collision_, fluid_, context, scene_, derived_.h, state_.maxSpeed);
}

RunState Simulation::runState() const {
  RunState s = state_;
  s.emitters.clear();
  for (const Emitter& e : emitters_) s.emitters.push_back(e.state());
  return s;
}

void Simulation::restore(const RunState& state, Particles fluid, std::vector<std::uint64_t> keys) {
  startKeys_ = std::move(keys);
  state_ = state;
  fluid_ = std::move(fluid);
  for (std::size_t e = 0; e < emitters_.size() && e < state.emitters.size(); ++e) {
    emitters_[e].setState(state.emitters[e]);
  }
  state_.emitters.clear();
}

}  // namespace sph::run
