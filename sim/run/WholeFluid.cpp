// The Decomposition of a run on one process: the whole fluid, nothing to agree on.
#include "sim/run/Decomposition.h"
#include "sim/run/Simulation.h"
#include "sim/solver/SphPasses.h"

namespace sph::run {
namespace {

class WholeFluid final : public Decomposition {
 public:
  void share(solver::StepContext&) override {}
  void findNeighbours(solver::StepContext& c, solver::StepProfile& profile,
                      bool neighbours) override {
    if (neighbours) solver::timed(profile, solver::Pass::Sort, [&] { sortParticles(c); });
  }
  void afterForces(Particles&, solver::StepProfile&, bool) override {}
  void agreeOnMotion(float&, float&) override {}
  bool owns(const Vec3&) const override { return true; }
  void collide(CollisionPass& pass, Particles& fluid, const CollisionContext& context,
               const scene::Scene&, float, float) override {
    pass.apply(fluid, context);
  }
  void guard(solver::StepContext& c, const scene::Scene& scene, std::uint64_t maxLost,
             RunState& state) override {
    const std::uint64_t lost =
        checkStability(c, scene.domain, state.step, state.time, state.lostParticles, maxLost);
    state.lostParticles += lost;
    if (lost == 0) return;
    // The next step's size follows the particles that stayed.
    const solver::MotionBounds bounds = solver::motionBounds(c.fluid);
    state.maxSpeed = bounds.maxSpeed, state.maxAcceleration = bounds.maxAcceleration;
  }
};

}  // namespace

std::unique_ptr<Decomposition> wholeFluid() {
  return std::make_unique<WholeFluid>();
}

}  // namespace sph::run
