// One SPH run: the state and the step (DESIGN.md, "The SPH stage"). A step is a fixed list of
// named, timed stages in step(); what varies between runs is chosen once, when the simulation is
// built: the fluid model (WCSPH, DFSPH or the particle model, sim/solver/FluidModel.h), the
// decomposition (the whole fluid, or a rank's slab of a distributed run, sim/run/Decomposition.h),
// the collision pass and the rain that feeds the fluid. Each pass is a function of an explicit
// StepContext (sim/solver/SphPasses.h) and writes only its own particles' slots, so a run is
// bit-identical for a given scene.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "sim/CollisionPass.h"
#include "sim/Particles.h"
#include "sim/grid/NeighbourGrid.h"
#include "sim/rain/FeedState.h"
#include "sim/run/Decomposition.h"
#include "sim/run/Emitter.h"
#include "sim/run/FluidFeed.h"
#include "sim/scene/Scene.h"
#include "sim/solver/Boundary.h"
#include "sim/solver/FluidModel.h"
#include "sim/solver/SceneSetup.h"
#include "sim/solver/StepContext.h"
#include "sim/solver/StepProfile.h"

namespace sph::rain {
class RainFeed;
}

namespace sph::run {

// Everything needed to continue a run exactly where it stopped (restart/resume).
struct RunState {
  double time = 0;
  std::uint64_t step = 0;
  float lastDt = 0;
  float maxSpeed = 0, maxAcceleration = 0;  // drive the next step size
  std::uint32_t nextId = 0;
  std::uint64_t lostParticles =
      0;  // removed for leaving the domain (SolverParams::maxLostParticles)
  std::vector<EmitterState> emitters;
  // The pressure solver's per-particle state (DFSPH's warm start, WCSPH's wall shares), in the
  // order of the fluid it was saved with.
  solver::PressureWarmStart warmStart;
  rain::FeedState rain;  // rain.feed_fluid: the landed rain (all zero without)
};

class Simulation {
 public:
  explicit Simulation(const scene::Scene& scene);
  // What a rank of a distributed run starts with: its slab of the scene's starting fluid, or no
  // fluid (a resume, whose restore() brings the rank's part of the cache's frame).
  enum class Start { Slab, Empty };
  // One rank of a distributed run (sim/run/StartSlab.h): generates only this rank's slab of the
  // starting fluid, cut as `start`'s first exchange will cut it, or (Start::Empty) none
  // (collective: every rank constructs its own at the same point, with the same `what`).
  // setHalo(start) must follow before any step.
  Simulation(const scene::Scene& scene, ranks::Halo& start, Start what = Start::Slab);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Advances by one adaptive step, never past `limit` (s): the step is shortened to land on it.
  // Throws StabilityError if the state stops being finite, or when more particles than the scene
  // tolerates have left the domain (those that leave are removed and counted).
  void step(double limit = 1e300);
  // Steps until time() == t exactly.
  void advanceTo(double t);
  // The scene's `settle`: steps the starting fluid for `seconds` with nothing added (no emitters,
  // no rain joining it, no collision pass), then starts the clock again: time() and stepCount()
  // read 0, the profile and the solve statistics are cleared, the particles and the solver's
  // state are the settled ones. `afterStep` (if set) follows each step; `stop` (if set) is asked
  // before each and true ends the settling early, with the clock left running (returns false).
  bool settle(double seconds, const std::function<void(const Simulation&)>& afterStep = {},
              const std::function<bool()>& stop = {});
  bool settling() const { return settling_; }

  double time() const { return state_.time; }
  std::uint64_t stepCount() const { return state_.step; }
  // Particles removed so far for leaving the domain.
  std::uint64_t lostParticles() const { return state_.lostParticles; }
  // The step size the next step() will take (before shortening to a limit).
  float nextTimeStep() const;

  const scene::Scene& scene() const { return scene_; }
  const solver::DerivedParams& params() const { return derived_; }
  const Particles& fluid() const { return fluid_; }
  Particles& fluid() { return fluid_; }
  const solver::Boundary& boundary() const { return boundary_; }
  const solver::StepProfile& profile() const { return profile_; }
  // Scale of the pressure force at the last step (1 / mean discrete gradient moment).
  float gradientCorrection() const { return gradientCorrection_; }
  // p_b / rho_b^2 (m^5 / (kg s^2)) of every boundary particle at the last step, in the order of
  // boundary().particles(): the pressure the walls pushed with (zeros for DFSPH's walls "none";
  // WCSPH's particles out of the fluid's reach keep their last value, which nothing reads).
  const std::vector<float>& boundaryPressureTerm() const { return boundaryFields_.pressureTerm; }
  const std::vector<Emitter>& emitters() const { return emitters_; }
  // rain.feed_fluid: the rain whose landed water joins the fluid at every tick (null without;
  // sim/rain/RainFeed.h). Its drops are part of the state: restore() leaves them as they are,
  // restoreRain() sets them.
  const rain::RainFeed* rainFeed() const { return feed_->rain(); }
  void restoreRain(double time, const std::vector<Vec3>& positions,
                   const std::vector<std::uint32_t>& generations);
  // The pressure solver's per-particle state, in the fluid's order (run state; a distributed run's
  // frames swap in the gathered one, job/distributed/DistributedRun.h).
  solver::PressureWarmStart& warmStart() { return state_.warmStart; }
  // The arrays of `w` that the solver carries per particle (those attached to a distributed run's
  // halo, in the same order).
  std::vector<std::vector<float>*> particleState(solver::PressureWarmStart& w) const;
  // What the DFSPH solvers did (zeros for WCSPH).
  const solver::PressureSolveStats& solveStats() const { return solveStats_; }

  void setCollisionPass(std::unique_ptr<CollisionPass> pass);
  const CollisionPass* collisionPass() const { return collision_.get(); }

  // Runs this simulation as one rank of a distributed run (sim/ranks/Halo.h, docs/scaling.md):
  // from now on the fluid is this rank's share. The caller keeps `halo` alive.
  void setHalo(ranks::Halo* halo);
  ranks::Halo* halo() const { return halo_; }

  RunState runState() const;
  // Replaces state and fluid with a saved one (the same scene must be loaded); a feeding rain's
  // drops are set apart, by restoreRain(). A distributed run's rank gives its part of the frame
  // with `keys`, the particles' indices in it (empty: the whole frame, or nothing).
  void restore(const RunState& state, Particles fluid, std::vector<std::uint64_t> keys = {});

 private:
  // Both public constructors: the scene's parameters, boundary and models; `start` null alone.
  Simulation(const scene::Scene& scene, ranks::Halo* start, Start what);
  // The constructors' work: the boundary's densities, the starting fluid (this rank's slab of
  // it with `start`) and the state that depends on it.
  void setUp(ranks::Halo* start, Start what);
  float chooseTimeStep() const;
  // This step's size: the next one, shortened to land on `limit` without a sliver before it.
  double stepSize(double limit) const;
  // The context the passes of a step of `dt` seconds work on.
  solver::StepContext context(float dt);
  void emitParticles(double dt);
  void collide(float dt);

  scene::Scene scene_;
  solver::DerivedParams derived_;
  solver::Boundary boundary_;
  Particles fluid_;
  std::vector<Emitter> emitters_;
  grid::NeighbourGrid grid_;
  std::unique_ptr<CollisionPass> collision_;
  solver::StepProfile profile_;
  RunState state_;
  solver::BoundaryFields boundaryFields_;
  solver::StepScratch scratch_;
  solver::WallStiffness walls_;
  float gradientCorrection_ = 1;  // scale of the pressure force this step
  solver::PressureSolveStats solveStats_;
  std::unique_ptr<solver::FluidModel> model_;
  std::unique_ptr<Decomposition> decomposition_;
  ranks::Halo* halo_ = nullptr;  // a distributed run's halo; null alone
  bool settling_ = false;        // within settle(): nothing joins the fluid
  // A distributed run's keys of the fluid (sim/ranks/Halo.h, adopt), handed to setHalo(): a slab
  // start's ids, a resumed slab's indices in the frame; empty when the fluid is whole (0, 1, ...).
  std::vector<std::uint64_t> startKeys_;
  Particles emittedElsewhere_;  // what another rank's emitters released (discarded)
  std::unique_ptr<FluidFeed> feed_;  // what joins the fluid at its ticks
};

}  // namespace sph::run
