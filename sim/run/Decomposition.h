// Which particles this process steps, and what it must agree on with the others: the whole fluid
// (one process, WholeFluid) or one rank's slab of a distributed run (HaloSlab, sim/ranks/Halo.h,
// docs/scaling.md). Chosen once, when the simulation is built or given its halo; the stages of
// Simulation::step() call it where a rank exchanges particles, ghosts or decisions with the
// others, so step() itself never asks which it is.
#pragma once

#include <cstdint>
#include <memory>

#include "sim/CollisionPass.h"
#include "sim/Particles.h"
#include "sim/Types.h"
#include "sim/scene/Scene.h"
#include "sim/solver/StepContext.h"
#include "sim/solver/StepProfile.h"

namespace sph::ranks {
class Halo;
}

namespace sph::run {

struct RunState;

class Decomposition {
 public:
  virtual ~Decomposition() = default;
  // What the passes need to know of the others: a rank's ghosts and communicator.
  virtual void share(solver::StepContext& c) = 0;
  // Before the neighbour passes: the fluid sorted by cell (a rank first takes its new slab and
  // ghosts). With `neighbours` false (the particle model), a rank only hands over the particles
  // that left its slab.
  virtual void findNeighbours(solver::StepContext& c, solver::StepProfile& profile,
                              bool neighbours) = 0;
  // After the forces: a rank drops the ghosts the neighbour passes needed.
  virtual void afterForces(Particles& fluid, solver::StepProfile& profile, bool neighbours) = 0;
  // The largest speed and acceleration over all processes (exact maxima).
  virtual void agreeOnMotion(float& maxSpeed, float& maxAcceleration) = 0;
  // Whether this process releases what an emitter at `p` emits.
  virtual bool owns(const Vec3& p) const = 0;
  // The collision pass on this process's particles, as one process would apply it to all.
  virtual void collide(CollisionPass& pass, Particles& fluid, const CollisionContext& context,
                       const scene::Scene& scene, float h, float maxSpeed) = 0;
  // The stability guard (solver::checkStability): removes the particles that left the domain,
  // counts them in `state`, throws StabilityError on every process if any stops the run.
  virtual void guard(solver::StepContext& c, const scene::Scene& scene, std::uint64_t maxLost,
                     RunState& state) = 0;
};

// One process holds the whole fluid.
std::unique_ptr<Decomposition> wholeFluid();
// One rank's slab of a distributed run; the caller keeps `halo` alive.
std::unique_ptr<Decomposition> haloSlab(ranks::Halo& halo);

}  // namespace sph::run
