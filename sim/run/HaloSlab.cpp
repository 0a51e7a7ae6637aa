// The Decomposition of one rank of a distributed run (docs/scaling.md): its slab of the fluid,
// the ghosts the neighbour passes need, and every decision taken over all ranks so that the
// frames are the single process's, bit for bit.
#include <optional>
#include <sstream>

#include "sim/InputError.h"
#include "sim/StabilityError.h"
#include "sim/grid/NeighbourGrid.h"
#include "sim/ranks/Halo.h"
#include "sim/run/Decomposition.h"
#include "sim/run/Simulation.h"
#include "sim/solver/SphPasses.h"

namespace sph::run {
namespace {

class HaloSlab final : public Decomposition {
 public:
  explicit HaloSlab(ranks::Halo& halo) : halo_(halo) {}

  void share(solver::StepContext& c) override {
    c.ghost = &halo_.ghost(), c.ranks = &halo_.comm(), c.halo = &halo_;
  }

  void findNeighbours(solver::StepContext& c, solver::StepProfile& profile,
                      bool neighbours) override {
    if (!neighbours) {  // migration only: no neighbour sums, no ghosts needed
      solver::timed(profile, solver::Pass::Exchange, [&] {
        halo_.exchange(c.fluid, c.derived.h);
        halo_.dropGhosts(c.fluid);
      });
      return;
    }
    float cellSize = 0;
    solver::timed(profile, solver::Pass::Exchange,
                  [&] { cellSize = halo_.exchange(c.fluid, c.derived.h); });
    solver::timed(profile, solver::Pass::Sort, [&] {
      c.grid.build(c.fluid.x.data(), c.fluid.y.data(), c.fluid.z.data(), c.fluid.size(), cellSize,
                   c.scratch.order, grid::NeighbourGrid::kExactCellSize);
      c.fluid.permute(c.scratch.order, c.scratch.permuteScratch);
      halo_.sorted(c.grid, c.scratch.order);
    });
  }

  void afterForces(Particles& fluid, solver::StepProfile& profile, bool neighbours) override {
    if (neighbours)
      solver::timed(profile, solver::Pass::Exchange, [&] { halo_.dropGhosts(fluid); });
  }

  void agreeOnMotion(float& maxSpeed, float& maxAcceleration) override {
    halo_.maxOverRanks(maxSpeed, maxAcceleration);
  }

  bool owns(const Vec3& p) const override { return halo_.owns(p); }

  void collide(CollisionPass& pass, Particles& fluid, const CollisionContext& context,
               const scene::Scene& scene, float h, float maxSpeed) override {
    if (scene.collision->method != scene::CollisionMethod::Exact) {
      // `octree` and `cdt-cpu` find pairs through structures of the whole fluid (an octree's
      // leaves, the CDT's depth images over the domain), which a rank's slab and ghosts would
      // build differently. So every rank gathers the whole fluid in the single-process order and
      // runs the pass on it, then keeps its own particles: the single process's result, bit for
      // bit, at the cost of the pass on every rank (not divided by K) and an all-gather of the
      // fluid each step (docs/scaling.md).
      std::vector<std::uint32_t> mine;
      Particles whole = halo_.allGather(fluid, mine);
      pass.apply(whole, context);
      fluid.assignFrom(whole, mine);
      return;
    }
    // `exact` (the only pass that runs distributed): a second exchange gives each rank the
    // particles within two cell planes of its slab, which holds every partner of its particles:
    // partners are closer than the range at the start of the step (x - v dt), so now closer than
    // range + 2 max speed dt. The exact detector picks the nearest partner and, among equally
    // near ones, the lowest index: the global order restricted to a rank keeps that choice, and
    // the response is per particle, so the result is the single process's, bit for bit.
    const float cs = halo_.exchange(fluid, h);
    const double reach =
        static_cast<double>(scene.collision->range) + 2.0 * double(maxSpeed) * context.dt;
    if (!(reach < ranks::kGhostPlanes * double(cs) * (1 - 1e-6))) {
      std::ostringstream msg;
      msg << scene.sourcePath << ": collision.range " << scene.collision->range
          << " m plus twice the step's travel reaches " << reach << " m, beyond the "
          << ranks::kGhostPlanes * cs
          << " m of ghosts a process receives (docs/scaling.md); run without mpirun or use a "
             "smaller range";
      throw InputError(msg.str());
    }
    pass.apply(fluid, context);
    halo_.dropGhosts(fluid);
  }

  void guard(solver::StepContext& c, const scene::Scene& scene, std::uint64_t maxLost,
             RunState& state) override {
    // The same decision over all ranks: the particles outside the domain are counted over the
    // ranks first, so each rank's check sees the count one process would (its own ones on top
    // of everyone else's) and removes its own, or all stop with the single process's message (a
    // non-finite state first, then the lowest particle id at fault).
    const Aabb& d = scene.domain;
    Particles& fluid = c.fluid;
    std::vector<std::uint8_t> keep;
    std::uint64_t outside = 0;
    for (std::size_t i = 0; i < fluid.size(); ++i) {
      const Vec3 x = fluid.position(i);
      if (!x.allFinite() || !fluid.velocity(i).allFinite() || d.contains(x)) continue;
      if (keep.empty()) keep.assign(fluid.size(), 1);
      keep[i] = 0, ++outside;
    }
    const std::uint64_t outsideAll = halo_.globalCount(outside);
    std::optional<StabilityError> local;
    try {
      const std::uint64_t lost = checkStability(
          c, d, state.step, state.time, state.lostParticles + outsideAll - outside, maxLost);
      if (lost > 0) halo_.removeLocal(keep);
    } catch (const StabilityError& e) {
      local = e;
    }
    halo_.agreeOnStability(local);
    if (outsideAll == 0) return;
    state.lostParticles += outsideAll;
    const solver::MotionBounds bounds = solver::motionBounds(fluid);
    state.maxSpeed = bounds.maxSpeed, state.maxAcceleration = bounds.maxAcceleration;
    halo_.maxOverRanks(state.maxSpeed, state.maxAcceleration);
  }

 private:
  ranks::Halo& halo_;
};

}  // namespace

std::unique_ptr<Decomposition> haloSlab(ranks::Halo& halo) {
  return std::make_unique<HaloSlab>(halo);
}

}  // namespace sph::run
