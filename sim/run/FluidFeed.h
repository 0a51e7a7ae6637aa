// What joins the fluid at set times, chosen once when the simulation is built: nothing, or the
// rain that lands in the water (rain.feed_fluid, sim/rain/RainFeed.h). Simulation::step() lands on
// the feed's next tick and feeds it there, whichever it is.
#pragma once

#include <memory>

#include "sim/Particles.h"
#include "sim/scene/Scene.h"

namespace sph::rain {
class RainFeed;
}

namespace sph::run {

struct RunState;

class FluidFeed {
 public:
  virtual ~FluidFeed() = default;
  // The first tick after `time` (s); never, without a feed.
  virtual double nextTick(double time) const = 0;
  // At the tick `tick`: adds what joined the fluid, counts it in `state`, and raises the next
  // step's speed bound to what entered.
  virtual void feed(double tick, Particles& fluid, RunState& state) = 0;
  // The rain behind the feed, or null.
  virtual rain::RainFeed* rain() { return nullptr; }
};

// The scene's feed: its rain when it feeds the fluid, else nothing.
std::unique_ptr<FluidFeed> fluidFeed(const scene::Scene& scene);

}  // namespace sph::run
