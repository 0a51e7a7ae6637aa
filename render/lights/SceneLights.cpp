#include "render/lights/SceneLights.h"

#include <cstdio>

#include "render/frame/Lighting.h"

namespace sph::render::lights {

SceneLights::SceneLights(const scene::Scene& scene, const scene::RenderDesc& render)
    : volume_(*scene.lights),
      render_(render),
      spacing_(scene.solver.spacing),
      background_(scene.lights->roomLight * frame::Lighting{}.background),
      solids_(sph::lights::lightSolids(scene)) {}

double SceneLights::update(const Particles& fluid, double time, const scene::CameraDesc* camera,
                           float aspect) {
  lights_ = sph::lights::lightParticles(volume_.desc(), fluid, time, solids_);
  if (camera && volume_.desc().cull) {
    const scene::RenderDesc& r = render_;
    if (aspect <= 0) aspect = static_cast<float>(r.width) / static_cast<float>(r.height);
    const LightView view = lightView(*camera, aspect, r.splatSize, r.kernelRadius, spacing_);
    seconds_ = volume_.update(lights_, &view);
  } else {
    seconds_ = volume_.update(lights_);
  }
  return seconds_;
}

std::string describeLights(const scene::LightsDesc& d) {
  char line[256];
  const std::string source = d.source == scene::LightSource::Emitter
                                 ? std::to_string(d.emitter.count) + " from an emitter"
                                 : std::string("every fluid particle");
  std::snprintf(line, sizeof line,
                "particle lights: %s, %d x %d x %d voxels of %g m, range %g m, %s filter%s, %s "
                "accumulation%s%s",
                source.c_str(), d.voxels[0], d.voxels[1], d.voxels[2], d.voxelSize, d.range,
                nameOf(d.filter), d.oversampling > 1 ? " oversampled" : "", nameOf(d.accumulate),
                d.pipeline != scene::LightPipeline::Deferred ? ""
                : d.shade == scene::LightShade::Cpu
                    ? ", deferred (G-buffer + lighting pass), shaded on the CPU"
                    : ", deferred (G-buffer + lighting pass)",
                d.cull ? ", culled to the view" : "");
  return line;
}

bool lightsNeedVelocity(const scene::Scene& scene) {
  return scene.lights && scene.lights->source == scene::LightSource::Fluid &&
         scene.lights->colouring == scene::LightColouring::Speed;
}

}  // namespace sph::render::lights
