// The particle lights of a scene in its pictures (scene section `lights`), for every command that
// draws (`run` with a render section, `render`, `compare`, `view`); a scene's frame
// (render/compose/SceneFrame.h) makes them its extra lights. No section, no volume, no light code.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/lights/LightVolume.h"
#include "sim/scene/Scene.h"

namespace sph::render::lights {

class SceneLights {
 public:
  // Allocates the volume (InputError if GL cannot) for pictures drawn with `render`. Needs a
  // current context.
  SceneLights(const scene::Scene& scene, const scene::RenderDesc& render);
  // The lights of the frame with fluid particles `fluid` (velocities too for colour_by "speed")
  // at simulated time `time` (s), accumulated into the volume. `camera`: the camera the frame is
  // drawn through, over a picture of width / height `aspect` (0: `render`'s); with
  // lights.cull only what it may see is accumulated (LightCulling.h). Null: the whole volume
  // (`view`, once its user moves the camera). Returns the seconds the volume took.
  double update(const Particles& fluid, double time, const scene::CameraDesc* camera = nullptr,
                float aspect = 0);

  LightVolume& volume() { return volume_; }
  // The colour of empty pixels under these lights: the room's light on the usual background.
  const Vec3& background() const { return background_; }
  const std::vector<sph::lights::LightParticle>& lights() const { return lights_; }
  double lastSeconds() const { return seconds_; }

 private:
  LightVolume volume_;
  scene::RenderDesc render_;
  float spacing_;  // m, the fluid's particle spacing
  Vec3 background_;
  std::vector<scene::Solid> solids_;
  std::vector<sph::lights::LightParticle> lights_;
  double seconds_ = 0;
};

// One line for the commands: "particle lights: 262144 from an emitter, 128 x 60 x 128 voxels of
// 0.01 m, trilinear, atomic accumulation", and the pipeline when deferred.
std::string describeLights(const scene::LightsDesc& desc);

// Whether drawing `scene`'s frames needs the particles' velocities (colour_by "speed" of fluid).
bool lightsNeedVelocity(const scene::Scene& scene);

}  // namespace sph::render::lights
