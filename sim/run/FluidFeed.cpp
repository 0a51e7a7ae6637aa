#include "sim/run/FluidFeed.h"

#include <algorithm>

#include "sim/rain/RainFeed.h"
#include "sim/run/Simulation.h"

namespace sph::run {
namespace {

class NoFeed final : public FluidFeed {
 public:
  double nextTick(double) const override { return 1e300; }
  void feed(double, Particles&, RunState&) override {}
};

class RainFeeding final : public FluidFeed {
 public:
  explicit RainFeeding(std::unique_ptr<rain::RainFeed> rain) : rain_(std::move(rain)) {}
  double nextTick(double time) const override { return rain_->nextTick(time); }
  void feed(double tick, Particles& fluid, RunState& state) override {
    const std::vector<Vec3>& landings = rain_->advanceTo(tick, fluid);
    if (rain_->addLandings(landings, state.rain, fluid, state.nextId) == 0) return;
    // The next step's size follows the new particles (they enter at the rain's speed).
    state.maxSpeed = std::max(state.maxSpeed, rain_->stepper().system().velocity().norm());
  }
  rain::RainFeed* rain() override { return rain_.get(); }

 private:
  std::unique_ptr<rain::RainFeed> rain_;
};

}  // namespace

std::unique_ptr<FluidFeed> fluidFeed(const scene::Scene& scene) {
  std::unique_ptr<rain::RainFeed> rain = rain::RainFeed::create(scene);
  if (!rain) return std::make_unique<NoFeed>();
  return std::make_unique<RainFeeding>(std::move(rain));
}

}  // namespace sph::run
