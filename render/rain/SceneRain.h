// The rain of a scene in its pictures (`run` with a render section, `render`, `view`). The rain
// is not simulated with the fluid nor stored in the cache: it is regenerated where it is drawn,
// deterministically, from the scene (rain seed, camera and camera.path, solids) and the times of
// the frames, because drops are a pure function of (seed, drop, respawn count) and the camera
// path is a function of time (docs/rain.md, "Replay"). Starting at time 0 it steps by the output
// frame interval with the camera of each step's time; the water stops drops at the frames that
// are drawn (their particles are at hand), the solids at every step.
#pragma once

#include <memory>
#include <vector>

#include "render/rain/RainRenderer.h"
#include "render/splat/FrameRenderer.h"
#include "sim/Particles.h"
#include "sim/Scene.h"
#include "sim/Solid.h"
#include "sim/rain/RainSystem.h"

namespace sph::render::rain {

class SceneRain {
 public:
  // Null if the scene has no rain section (nothing is allocated then). Needs a current context.
  // `aspect`: the pictures' width / height.
  static std::unique_ptr<SceneRain> create(const Scene& scene, float aspect);

  // Brings the drops to `time` (s) and uploads them to the layer; `fluid` is the water at `time`.
  // Going back in time starts again from 0.
  void advanceTo(double time, const Particles& fluid);
  // Keeps the drops where `camera` looks without moving them (an update of 0 s: drops out of its
  // rain space are respawned in it), for a camera the user flies (`view`). Uploads them.
  void follow(const CameraDesc& camera);
  RainRenderer& layer() { return renderer_; }
  const sph::rain::RainSystem& system() const { return system_; }
  // Seconds spent in the rain update (CPU) and the upload, cumulative.
  double updateSeconds() const { return updateSeconds_; }

 private:
  SceneRain(const Scene& scene, float aspect);
  CameraDesc camera_;
  CameraPath path_;
  double interval_;
  float waterCell_;
  std::vector<Solid> solids_;
  sph::rain::RainSystem system_;
  RainRenderer renderer_;
  double time_ = -1;
  double updateSeconds_ = 0;
};

// Sets up `renderer` to draw the rain of `scene` (null and nothing done without a rain section):
// its streaks as a layer after the splats, beside the opaque `solids` (null if not drawn), and
// its spotlight on the water and solids. Keep the result alive while `renderer` draws.
std::unique_ptr<SceneRain> showRain(const Scene& scene, splat::FrameRenderer& renderer,
                                    splat::FrameLayer* solids);

}  // namespace sph::render::rain
