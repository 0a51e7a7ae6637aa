// The rain of a scene over time (docs/rain.md, "Replay"), without GL or files: the drops of
// sim/rain/RainSystem stepped at the scene's output frames with the camera of each frame's time
// (camera and camera.path) and stopped by the solids and by the water of the frames it is given.
// `run` steps it beside the fluid and stores its drops in the cache (io/cache/RainCache.h); `render`
// and `view` redraw those, or, for a cache written without them, regenerate them from time 0:
// drops are a pure function of (seed, drop, respawn count), so both give the same drops.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "sim/scene/Camera.h"
#include "sim/Particles.h"
#include "sim/scene/Scene.h"
#include "sim/scene/Solid.h"
#include "sim/rain/RainSystem.h"

namespace sph::rain {

class RainStepper {
 public:
  // Null if the scene has no rain section (or no camera): nothing is allocated then. `aspect`:
  // the rain camera's width / height (the pictures').
  static std::unique_ptr<RainStepper> create(const scene::Scene& scene, float aspect);
  // The aspect of the scene's pictures (its render section, else the default picture size).
  static float sceneAspect(const scene::Scene& scene);

  // Brings the drops to `time` (s): steps of the output frame interval from the last time (from
  // 0 after a reset, and again from 0 when `time` lies before it). `fluid` is the water at
  // `time`: it stops drops at the last step; the solids stop them at every step.
  void advanceTo(double time, const Particles& fluid);
  // The same with the water given as its occupied cells (of waterCell()'s edge): an MPI run's
  // rank 0 steps the drops with the union of its ranks' cells and never holds the whole fluid.
  void advanceTo(double time, const WaterCells& water);
  // The edge (m) of the water cells that stop the drops of `scene`: two spacings, so the
  // particles of a body of water leave none of them empty.
  static float waterCell(const scene::Scene& scene) { return 2 * scene.solver.spacing; }
  // Keeps the drops where `camera` looks without moving them (an update of 0 s).
  void follow(const scene::CameraDesc& camera);
  // Continues from a stored state (a resume): the drops at `time` as advanceTo left them.
  void restore(double time, const std::vector<Vec3>& positions,
               const std::vector<std::uint32_t>& generations);

  const RainSystem& system() const { return system_; }
  double time() const { return time_; }

 private:
  RainStepper(const scene::Scene& scene, float aspect);
  scene::CameraDesc camera_;
  scene::CameraPath path_;
  double interval_;
  float waterCell_;
  std::vector<scene::Solid> solids_;
  RainSystem system_;
  double time_ = -1;
};

}  // namespace sph::rain
