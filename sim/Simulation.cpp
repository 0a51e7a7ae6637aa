#include "sim/Simulation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/Parallel.h"
#include "sim/StabilityError.h"

namespace sph {

Simulation::Simulation(const Scene& scene)
    : scene_(scene),
      derived_(deriveParams(scene)),
      boundary_(scene.boundaries, scene.domain, scene.solver.spacing, derived_.boundaryLayers,
                derived_.h) {
  computeStaticBoundaryDensity();
  gradientCorrection_ = derived_.gradientCorrection;
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

void Simulation::step(double limit) {
  double dt = chooseTimeStep();
  if (state_.time + dt > limit) dt = limit - state_.time;
  // Avoid a sliver step right before the limit: split the remainder into two equal steps.
  else if (state_.time + 1.5 * dt > limit)
    dt = 0.5 * (limit - state_.time);
  const float dtf = static_cast<float>(dt);
  {
    PassTimer t(profile_, Pass::Emit);
    emitParticles(dt);
  }
  // The paper's particle model has no neighbour passes, so nothing to sort for.
  const bool sph = scene_.solver.model == SolverModel::Sph;
  if (sph) {
    PassTimer t(profile_, Pass::Sort);
    sortParticles();
  }
  if (sph) {
    PassTimer t(profile_, Pass::Density);
    computeDensity();
  }
  if (sph) {
    PassTimer t(profile_, Pass::Pressure);
    computePressure();
  }
  {
    PassTimer t(profile_, Pass::Forces);
    if (sph)
      computeForces();
    else
      applyGravityOnly();
  }
  {
    PassTimer t(profile_, Pass::Integrate);
    integrate(dtf);
  }
  state_.time += dt;
  state_.step += 1;
  state_.lastDt = dtf;
  {
    PassTimer t(profile_, Pass::Collide);
    collide(dtf);
  }
  {
    PassTimer t(profile_, Pass::Boundaries);
    enforceBoundaries(dtf);
  }
  {
    PassTimer t(profile_, Pass::Guard);
    checkStability();
  }
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

void Simulation::sortParticles() {
  grid_.build(fluid_.x.data(), fluid_.y.data(), fluid_.z.data(), fluid_.size(), derived_.h, order_);
  fluid_.permute(order_, permuteScratch_);
}

// The paper's particles feel gravity only; they interact through the collision pass alone.
void Simulation::applyGravityOnly() {
  Particles& f = fluid_;
  const Vec3 g = scene_.solver.gravity;
  parallelFor(f.size(), [&](std::size_t i) { f.ax[i] = g.x(), f.ay[i] = g.y(), f.az[i] = g.z(); });
}

// Symplectic Euler: velocities first, then positions with the new velocities.
void Simulation::integrate(float dt) {
  Particles& f = fluid_;
  const std::size_t n = f.size();
  parallelFor(n, [&](std::size_t i) {
    f.vx[i] += dt * f.ax[i], f.vy[i] += dt * f.ay[i], f.vz[i] += dt * f.az[i];
    f.x[i] += dt * f.vx[i], f.y[i] += dt * f.vy[i], f.z[i] += dt * f.vz[i];
  });
  // Largest speed and acceleration for the next step size. max is exact, so the split of the
  // reduction between threads does not change the result.
  float v2 = 0, a2 = 0;
#pragma omp parallel for reduction(max : v2, a2) schedule(static)
  for (long long i = 0; i < static_cast<long long>(n); ++i) {
    v2 = std::max(v2, f.vx[i] * f.vx[i] + f.vy[i] * f.vy[i] + f.vz[i] * f.vz[i]);
    a2 = std::max(a2, f.ax[i] * f.ax[i] + f.ay[i] * f.ay[i] + f.az[i] * f.az[i]);
  }
  state_.maxSpeed = std::sqrt(v2);
  state_.maxAcceleration = std::sqrt(a2);
}

void Simulation::collide(float dt) {
  if (!collision_) return;
  CollisionContext context;
  context.time = state_.time;
  context.dt = dt;
  context.step = state_.step;
  collision_->apply(fluid_, context);
}

void Simulation::enforceBoundaries(float dt) {
  if (boundary_.solids().empty()) return;
  Particles& f = fluid_;
  parallelFor(f.size(), [&](std::size_t i) {
    Vec3 x = f.position(i), v = f.velocity(i);
    const Vec3 xOld = x - dt * v;
    if (boundary_.enforce(xOld, x, v)) f.setPosition(i, x), f.setVelocity(i, v);
  });
}

void Simulation::checkStability() const {
  const Particles& f = fluid_;
  const std::size_t n = f.size();
  // Fast vectorisable screen; only when it fails do we look for the first culprit.
  int bad = 0;
  const Aabb& d = scene_.domain;
#pragma omp parallel for reduction(| : bad) schedule(static)
  for (long long i = 0; i < static_cast<long long>(n); ++i) {
    const bool finite = std::isfinite(f.x[i] + f.y[i] + f.z[i] + f.vx[i] + f.vy[i] + f.vz[i]);
    const bool inside = f.x[i] >= d.lo.x() && f.x[i] <= d.hi.x() && f.y[i] >= d.lo.y() &&
                        f.y[i] <= d.hi.y() && f.z[i] >= d.lo.z() && f.z[i] <= d.hi.z();
    bad |= (!finite || !inside) ? 1 : 0;
  }
  if (!bad) return;
  // Report the lowest particle id at fault, so the message does not depend on the sort.
  std::size_t worst = n;
  bool worstFinite = true;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 x = f.position(i), v = f.velocity(i);
    const bool finite = x.allFinite() && v.allFinite();
    if ((finite && d.contains(x)) || (worst < n && f.id[i] > f.id[worst])) continue;
    worst = i, worstFinite = finite;
  }
  // The screen sums six values: finite ones near FLT_MAX can overflow it with every particle
  // finite and inside. Nothing to report then (and no index n to read).
  if (worst == n) return;
  const Vec3 x = f.position(worst), v = f.velocity(worst);
  std::ostringstream msg;
  msg.precision(6);
  msg << "numerical blow-up at step " << state_.step << ", t = " << state_.time << " s: particle "
      << f.id[worst];
  if (!worstFinite) {
    msg << " has a non-finite state";
  } else {
    msg << " left the domain [" << d.lo.x() << ", " << d.lo.y() << ", " << d.lo.z() << "] - ["
        << d.hi.x() << ", " << d.hi.y() << ", " << d.hi.z() << "]";
  }
  msg << " (position " << x.x() << ", " << x.y() << ", " << x.z() << " m; velocity " << v.x()
      << ", " << v.y() << ", " << v.z() << " m/s; last dt " << state_.lastDt << " s)";
  throw StabilityError(
      worstFinite ? StabilityError::Kind::LeftDomain : StabilityError::Kind::NonFinite, state_.step,
      state_.time, f.id[worst], x, v, msg.str());
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
