#include "sim/run/Simulation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "sim/Assert.h"
#include "sim/InputError.h"
#include "sim/solver/SphPasses.h"
#include "sim/solver/Validate.h"
#include "sim/run/StartSlab.h"

namespace sph::run {

Simulation::Simulation(const scene::Scene& scene)
    : scene_(scene),
      derived_(solver::deriveParams(scene)),
      boundary_(scene.boundaries, scene.domain, scene.solver.spacing, derived_.boundaryLayers,
                derived_.h) {
  setUp(nullptr, Start::Slab);
}

Simulation::Simulation(const scene::Scene& scene, ranks::Halo& start, Start what)
    : scene_(scene),
      derived_(solver::deriveParams(scene)),
      boundary_(scene.boundaries, scene.domain, scene.solver.spacing, derived_.boundaryLayers,
                derived_.h) {
  setUp(&start, what);
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
    emitters_.emplace_back(e, scene_.solver.spacing);
  state_.maxAcceleration = scene_.solver.gravity.norm();
  for (std::size_t i = 0; i < fluid_.size(); ++i) {
    state_.maxSpeed = std::max(state_.maxSpeed, fluid_.velocity(i).norm());
  }
  if (start) start->maxOverRanks(state_.maxSpeed, state_.maxAcceleration);  // exact maxima
  rainFeed_ = rain::RainFeed::create(scene_);
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
      dt,       scene_.solver,       derived_,         boundary_,  fluid_, grid_, boundaryFields_,
      scratch_, gradientCorrection_, state_.warmStart, solveStats_};
  if (halo_) c.ghost = &halo_->ghost(), c.ranks = &halo_->comm(), c.halo = halo_;
  return c;
}

void Simulation::setHalo(ranks::Halo* halo) {
  halo_ = halo;
  if (!halo_) return;
  // The particles' places in the starting order (a slab start's ids, a resumed slab's indices in
  // the frame), or none: a whole fluid is in that order from 0.
  halo_->adopt(fluid_, std::move(startKeys_));
  startKeys_.clear();
  // DFSPH's warm start is run state per particle: it moves with its particle (docs/scaling.md).
  if (scene_.solver.model == scene::SolverModel::Sph &&
      scene_.solver.pressure == scene::PressureSolver::Dfsph) {
    halo_->attach(state_.warmStart.density);
    halo_->attach(state_.warmStart.divergence);
  }
}

void Simulation::step(double limit) {
  // A feeding rain steps at its ticks: the step lands on the next one.
  const double rainTick = rainFeed_ ? rainFeed_->nextTick(state_.time) : 1e300;
  limit = std::min(limit, rainTick);
  double dt = chooseTimeStep();
  if (state_.time + dt > limit) dt = limit - state_.time;
  // Avoid a sliver step right before the limit: split the remainder into two equal steps.
  else if (state_.time + 1.5 * dt > limit)
    dt = 0.5 * (limit - state_.time);
  solver::StepContext c = context(static_cast<float>(dt));
  auto timed = [&](solver::Pass pass, auto&& run) {
    solver::PassTimer t(profile_, pass);
    run();
  };
  timed(solver::Pass::Emit, [&] { emitParticles(dt); });
  // The paper's particle model has no neighbour passes, so nothing to sort for.
  const bool sph = scene_.solver.model == scene::SolverModel::Sph;
  const bool dfsph = sph && scene_.solver.pressure == scene::PressureSolver::Dfsph;
  if (sph) {
    if (halo_) {
      float cellSize = 0;
      timed(solver::Pass::Exchange, [&] { cellSize = halo_->exchange(fluid_, derived_.h); });
      timed(solver::Pass::Sort, [&] {
        grid_.build(fluid_.x.data(), fluid_.y.data(), fluid_.z.data(), fluid_.size(), cellSize,
                    scratch_.order, grid::NeighbourGrid::kExactCellSize);
        fluid_.permute(scratch_.order, scratch_.permuteScratch);
        halo_->sorted(grid_, scratch_.order);
      });
    } else {
      timed(solver::Pass::Sort, [&] { sortParticles(c); });
    }
    // DFSPH's density comes with its factor and pairs, from one neighbour search.
    if (dfsph)
      timed(solver::Pass::Factor, [&] { computeDfsphDensityAndFactor(c); });
    else
      timed(solver::Pass::Density, [&] { computeDensity(c); });
    validate("the density pass",
             [&] { return checkDensity(fluid_, derived_, scene_.solver.densityKernel); });
  }
  if (dfsph) {  // sim/solver/Dfsph.cpp
    timed(solver::Pass::Divergence, [&] { solveDivergence(c); });
    timed(solver::Pass::Forces, [&] { computeDfsphViscosity(c), predictVelocity(c); });
    timed(solver::Pass::Pressure, [&] { solveDensity(c); });
    if (halo_) timed(solver::Pass::Exchange, [&] { halo_->dropGhosts(fluid_); });
  } else if (sph) {
    timed(solver::Pass::Pressure, [&] { computePressure(c); });
    timed(solver::Pass::Forces, [&] { computeForces(c); });
    if (halo_) timed(solver::Pass::Exchange, [&] { halo_->dropGhosts(fluid_); });
  } else {
    if (halo_) {  // migration only: no neighbour sums, no ghosts needed
      timed(solver::Pass::Exchange, [&] {
        halo_->exchange(fluid_, derived_.h);
        halo_->dropGhosts(fluid_);
      });
    }
    timed(solver::Pass::Forces, [&] { applyGravityOnly(c); });
  }
  timed(solver::Pass::Integrate, [&] {
    const solver::MotionBounds bounds = dfsph ? integratePositions(c) : integrate(c);
    state_.maxSpeed = bounds.maxSpeed, state_.maxAcceleration = bounds.maxAcceleration;
    if (halo_) halo_->maxOverRanks(state_.maxSpeed, state_.maxAcceleration);
  });
  state_.time += dt;
  state_.step += 1;
  state_.lastDt = c.dt;
  timed(solver::Pass::Collide, [&] { collide(c.dt); });
  timed(solver::Pass::Boundaries, [&] { enforceBoundaries(c); });
  timed(solver::Pass::Guard, [&] {
    if (!halo_) {
      const std::uint64_t lost = checkStability(c, scene_.domain, state_.step, state_.time,
                                                state_.lostParticles, derived_.maxLostParticles);
      state_.lostParticles += lost;
      if (lost == 0) return;
      // The next step's size follows the particles that stayed.
      const solver::MotionBounds bounds = solver::motionBounds(fluid_);
      state_.maxSpeed = bounds.maxSpeed, state_.maxAcceleration = bounds.maxAcceleration;
      return;
    }
    // On K processes the same decision over all ranks: the particles outside the domain are
    // counted over the ranks first, so each rank's check sees the count one process would (its
    // own ones on top of everyone else's) and removes its own, or all stop with the single
    // process's message (a non-finite state first, then the lowest particle id at fault).
    const Aabb& d = scene_.domain;
    std::vector<std::uint8_t> keep;
    std::uint64_t outside = 0;
    for (std::size_t i = 0; i < fluid_.size(); ++i) {
      const Vec3 x = fluid_.position(i);
      if (!x.allFinite() || !fluid_.velocity(i).allFinite() || d.contains(x)) continue;
      if (keep.empty()) keep.assign(fluid_.size(), 1);
      keep[i] = 0, ++outside;
    }
    const std::uint64_t outsideAll = halo_->globalCount(outside);
    std::optional<StabilityError> local;
    try {
      const std::uint64_t lost =
          checkStability(c, d, state_.step, state_.time,
                         state_.lostParticles + outsideAll - outside, derived_.maxLostParticles);
      if (lost > 0) halo_->removeLocal(keep);
    } catch (const StabilityError& e) {
      local = e;
    }
    halo_->agreeOnStability(local);
    if (outsideAll == 0) return;
    state_.lostParticles += outsideAll;
    const solver::MotionBounds bounds = solver::motionBounds(fluid_);
    state_.maxSpeed = bounds.maxSpeed, state_.maxAcceleration = bounds.maxAcceleration;
    halo_->maxOverRanks(state_.maxSpeed, state_.maxAcceleration);
  });
  if (state_.time >= rainTick) timed(solver::Pass::Emit, [&] { feedRain(rainTick); });
  validate("the step", [&] { return solver::checkState(fluid_, state_.nextId); });
  profile_.steps += 1;
  profile_.particleSteps += fluid_.size();
}

void Simulation::advanceTo(double t) {
  while (state_.time < t) step(t);
}

void Simulation::emitParticles(double dt) {
  const double end = state_.time + dt;
  for (std::size_t e = 0; e < emitters_.size(); ++e) {
    // Distributed: the rank holding the nozzle releases the particles; the others advance the
    // emitter's state and the ids alike.
    Particles& into =
        !halo_ || halo_->owns(scene_.emitters[e].position) ? fluid_ : emittedElsewhere_;
    emitters_[e].emit(end, dt, into, state_.nextId, scene_.solver.restDensity);
  }
  emittedElsewhere_.clear();
}

void Simulation::feedRain(double tick) {
  const std::vector<Vec3>& landings = rainFeed_->advanceTo(tick, fluid_);
  if (rainFeed_->addLandings(landings, state_.rain, fluid_, state_.nextId) == 0) return;
  // The next step's size follows the new particles (they enter at the rain's speed).
  state_.maxSpeed = std::max(state_.maxSpeed, rainFeed_->stepper().system().velocity().norm());
}

void Simulation::restoreRain(double time, const std::vector<Vec3>& positions,
                             const std::vector<std::uint32_t>& generations) {
  if (rainFeed_) rainFeed_->restore(time, positions, generations);
}

void Simulation::collide(float dt) {
  if (!collision_) return;
  CollisionContext context;
  context.time = state_.time;
  context.dt = dt;
  context.step = state_.step;
  if (!halo_) {
    collision_->apply(fluid_, context);
    return;
  }
  if (scene_.collision->method != scene::CollisionMethod::Exact) {
    // `octree` and `cdt-cpu` find pairs through structures of the whole fluid (an octree's
    // leaves, the CDT's depth images over the domain), which a rank's slab and ghosts would
    // build differently. So every rank gathers the whole fluid in the single-process order and
    // runs the pass on it, then keeps its own particles: the single process's result, bit for
    // bit, at the cost of the pass on every rank (not divided by K) and an all-gather of the
    // fluid each step (docs/scaling.md).
    std::vector<std::uint32_t> mine;
    Particles whole = halo_->allGather(fluid_, mine);
    collision_->apply(whole, context);
    fluid_.assignFrom(whole, mine);
    return;
  }
  // `exact` (the only pass that runs distributed): a second exchange gives
  // each rank the particles within two cell planes of its slab, which holds every partner of its
  // particles: partners are closer than the range at the start of the step (x - v dt), so now
  // closer than range + 2 max speed dt. The exact detector picks the nearest partner and, among
  // equally near ones, the lowest index: the global order restricted to a rank keeps that choice,
  // and the response is per particle, so the result is the single process's, bit for bit.
  const float cs = halo_->exchange(fluid_, derived_.h);
  const double reach =
      static_cast<double>(scene_.collision->range) + 2.0 * double(state_.maxSpeed) * dt;
  if (!(reach < ranks::kGhostPlanes * double(cs) * (1 - 1e-6))) {
    std::ostringstream msg;
    msg << scene_.sourcePath << ": collision.range " << scene_.collision->range
        << " m plus twice the step's travel reaches " << reach << " m, beyond the "
        << ranks::kGhostPlanes * cs
        << " m of ghosts a process receives (docs/scaling.md); run without mpirun or use a "
           "smaller range";
    throw InputError(msg.str());
  }
  collision_->apply(fluid_, context);
  halo_->dropGhosts(fluid_);
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
