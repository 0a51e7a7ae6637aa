// The particle lights' error figures on a picture (`sphsplat compare` on a scene with `lights`;
// docs/lights.md, "Error figures"): the solids are drawn into a G-buffer (world position and
// normal per pixel), the shading's particle-light term is evaluated there through each filter
// (the GPU code of shaders/extra_lights.glsl, via LightVolume::probe, or with lights.shade "cpu"
// the CPU's for the filters it has: LightVolume::shade) and the exact sum over the lights
// (ExactLights) at the same points; diffuse and specular apart. Needs a current context.
#pragma once

#include <string>
#include <vector>

#include "render/frame/RenderImage.h"
#include "render/lights/ExactLights.h"
#include "render/lights/LightVolume.h"
#include "render/solids/SolidRenderer.h"

namespace sph::render::lights {

// Pixels covered by a solid, with their shading points.
struct SolidGBuffer {
  int width = 0, height = 0;
  std::vector<ProbePoint> points;
  std::vector<std::size_t> pixels;  // row 0 at the top
};
SolidGBuffer solidGBuffer(solids::SolidRenderer& solids, const scene::CameraDesc& camera, int width,
                          int height,
                          const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());

// The particle light alone (diffuse + specular) on the solids, as an sRGB picture (black
// elsewhere), and its error figures against the exact sum.
struct LightComparison {
  std::string name;  // "nearest", ..., "exact"
  frame::RenderImage image;
  LightError total, diffuse, specular;
  double seconds = 0;  // evaluating the points (GPU probe, CPU shading or CPU sum)
};

// The exact image first, then one per (filter, tension, oversampling) in `settings`, with
// `volume` already updated with `lights`.
struct FilterSetting {
  scene::LightFilter filter = scene::LightFilter::Trilinear;
  float tension = 0;
  int oversampling = 1;
  std::string label() const;
};
std::vector<LightComparison> compareLights(LightVolume& volume,
                                           const std::vector<sph::lights::LightParticle>& lights,
                                           const SolidGBuffer& gbuffer, const Vec3& base,
                                           const std::vector<FilterSetting>& settings);

}  // namespace sph::render::lights
