// rain.feed_fluid (docs/rain.md, "Rain that fills the pool"): the rain that lands in
// the water joins the SPH fluid instead of vanishing (the paper). The drops are stepped at the
// scene's output frame times ("ticks", k / output.fps, where `run` writes its frames) by their
// own RainStepper, with the water of that moment; Simulation::step lands on every tick and hands
// the drops that landed to addLandings(), which turns each particle's worth of landed water into
// one fluid particle. Nothing of this exists unless the scene's rain feeds the fluid.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "sim/Particles.h"
#include "sim/rain/FeedState.h"
#include "sim/rain/RainStepper.h"
#include "sim/scene/Scene.h"

namespace sph::rain {

class RainFeed {
 public:
  // Null unless the scene has a rain section with feed_fluid (and a camera). The drops start
  // as the rain of the scene starts at t = 0.
  static std::unique_ptr<RainFeed> create(const scene::Scene& scene);

  // The first tick after `time` (s).
  double nextTick(double time) const;
  // Steps the drops to the tick `time` with the water `fluid` (at that time); returns where the
  // drops that landed in it entered, in drop order (RainSystem::landings).
  const std::vector<Vec3>& advanceTo(double time, const Particles& fluid);
  // Adds the water of `landings` to `state`, and for each particle's worth one fluid particle
  // (rest density, ids from `nextId`) moving with the rain's velocity, above the landing that
  // completes it: the first point straight above with no particle within a spacing. Returns the
  // particles added.
  std::size_t addLandings(const std::vector<Vec3>& landings, FeedState& state, Particles& fluid,
                          std::uint32_t& nextId) const;
  // Continues the drops from a stored state (a resume): the drops at `time`.
  void restore(double time, const std::vector<Vec3>& positions,
               const std::vector<std::uint32_t>& generations);

  const RainStepper& stepper() const { return *stepper_; }
  // m^3: one fluid particle's water, spacing^3.
  double particleVolume() const { return particleVolume_; }
  double dropVolume() const { return dropVolume_; }

 private:
  explicit RainFeed(const scene::Scene& scene);
  std::unique_ptr<RainStepper> stepper_;
  double interval_;
  double particleVolume_, dropVolume_;
  float restDensity_;
  float spacing_;  // m
  // Quarter spacings a new particle may be raised above its landing to a free place.
  static constexpr int kMaxRise = 80;
};

}  // namespace sph::rain
