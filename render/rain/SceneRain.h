// The rain of a scene in its pictures (`run` with a render section, `render`, `view`): the drops
// of a sim/rain/RainStepper uploaded to a RainRenderer layer. `run` steps the rain beside the
// fluid and stores its drops in the cache (io/cache/RainCache.h); `render` and `view` redraw the
// stored drops (restore()), or, for a cache without them, regenerate them deterministically from
// the scene and the frame times (advanceTo(); docs/rain.md, "Replay"). A scene's frame
// (render/compose/SceneFrame.h) draws its layer after the water and lights the water and solids
// with its spotlight.
#pragma once

#include <memory>
#include <vector>

#include "render/rain/RainRenderer.h"
#include "sim/Particles.h"
#include "sim/rain/RainStepper.h"
#include "sim/scene/Scene.h"

namespace sph::render::rain {

class SceneRain {
 public:
  // Null if the scene has no rain section (nothing is allocated then). Needs a current context.
  // `aspect`: the pictures' width / height.
  static std::unique_ptr<SceneRain> create(const scene::Scene& scene, float aspect);

  // Brings the drops to `time` (s) and uploads them to the layer; `fluid` is the water at `time`.
  // Going back in time starts again from 0.
  void advanceTo(double time, const Particles& fluid);
  // Takes the drops a run stored for `time` (io/cache/RainCache.h) and uploads them.
  void restore(double time, const std::vector<Vec3>& positions,
               const std::vector<std::uint32_t>& generations);
  // Uploads the drops of another stepper (the run's own, which the cache stores).
  void show(const sph::rain::RainSystem& drops);
  // Keeps the drops where `camera` looks without moving them (an update of 0 s: drops out of its
  // rain space are respawned in it), for a camera the user flies (`view`). Uploads them.
  void follow(const scene::CameraDesc& camera);
  RainRenderer& layer() { return renderer_; }
  const sph::rain::RainSystem& system() const { return stepper_->system(); }
  // Seconds spent in the rain update (CPU) and the upload, cumulative.
  double updateSeconds() const { return updateSeconds_; }

 private:
  SceneRain(const scene::Scene& scene, float aspect);
  std::unique_ptr<sph::rain::RainStepper> stepper_;
  RainRenderer renderer_;
  double updateSeconds_ = 0;
};

}  // namespace sph::render::rain
