// The particle lights of a scene in its pictures (scene section `lights`): one place for every
// command that draws (`run` with a render section, `render`, `compare`, `view`). No section, no
// volume, no light code.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/lights/LightVolume.h"
#include "render/splat/FrameRenderer.h"
#include "sim/scene/Scene.h"

namespace sph::render::lights {

class SceneLights {
 public:
  // Allocates the volume (InputError if GL cannot) and makes it `renderer`'s extra lights. Keep
  // it alive while `renderer` draws. Needs a current context.
  SceneLights(const scene::Scene& scene, splat::FrameRenderer& renderer);
  // The lights of the frame with fluid particles `fluid` (velocities too for colour_by "speed")
  // at simulated time `time` (s), accumulated into the volume. `camera`: the camera the frame is
  // drawn through, over a picture of width / height `aspect` (0: the renderer's); with
  // lights.cull only what it may see is accumulated (LightCulling.h). Null: the whole volume
  // (`view`, once its user moves the camera). Returns the seconds the volume took.
  double update(const Particles& fluid, double time, const scene::CameraDesc* camera = nullptr,
                float aspect = 0);

  LightVolume& volume() { return volume_; }
  const std::vector<sph::lights::LightParticle>& lights() const { return lights_; }
  double lastSeconds() const { return seconds_; }

 private:
  LightVolume volume_;
  const splat::FrameRenderer& renderer_;
  std::vector<scene::Solid> solids_;
  std::vector<sph::lights::LightParticle> lights_;
  double seconds_ = 0;
};

// A SceneLights for `scene` when it has a `lights` section, else null.
std::unique_ptr<SceneLights> showLights(const scene::Scene& scene, splat::FrameRenderer& renderer);

// One line for the commands: "particle lights: 262144 from an emitter, 128 x 60 x 128 voxels of
// 0.01 m, trilinear, atomic accumulation", and the pipeline when deferred.
std::string describeLights(const scene::LightsDesc& desc);

// Whether drawing `scene`'s frames needs the particles' velocities (colour_by "speed" of fluid).
bool lightsNeedVelocity(const scene::Scene& scene);

}  // namespace sph::render::lights
