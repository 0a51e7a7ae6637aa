// The one lighting model of the renderers (DESIGN.md, "Gouraud shading ... optional environment
// reflection and alpha"): the GL splat shaders evaluate it per vertex (shaders/splat_shading.glsl,
// fed by Lighting's uniforms) and the reference ray-marcher per pixel (shade() below), so the two
// differ only by where the normal comes from. tests/test_splat_gl.cpp checks they agree on a flat
// splat.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "sim/Types.h"
#include "sim/scene/RainDesc.h"

namespace sph::render::frame {

class ExtraLights;

struct Lighting {
  Vec3 toLight = Vec3(0.35f, 0.85f, 0.4f).normalized();  // unit, towards a directional light
  Vec3 base = Vec3(0.16f, 0.42f, 0.78f);                 // water colour (linear RGB)
  Vec3 background = Vec3(0.93f, 0.94f, 0.96f);           // empty pixels
  float ambient = 0.25f, diffuse = 0.7f, specular = 0.5f, shininess = 48.0f;
  bool environment = true;  // reflect a sky gradient (Schlick Fresnel)
  Vec3 horizon = Vec3(0.85f, 0.88f, 0.92f), zenith = Vec3(0.35f, 0.55f, 0.85f);
  float fresnelMin = 0.06f;  // reflectance at normal incidence
  float alpha = 1.0f;        // < 1: blend splats (the paper's transparent water); metrics use 1
  // Position-dependent lights of the GL shaders (render/frame/ExtraLights.h), not owned; null:
  // none. shade() below never has them (the reference ray-marcher is lit by the scene's light).
  const ExtraLights* extra = nullptr;
  // The rain's cone spotlight (seed 002 section 3.2), lighting water and solids in the GL frame
  // through shaders/extra_lights.glsl; not in shade() below (the reference ray-marcher and the
  // error figures never see it). None: no rain spotlight.
  std::optional<scene::SpotlightDesc> spotlight;
};

// Colour of a surface point with outward unit normal n seen along unit `toEye`, in [0, 1].
inline Vec3 shade(const Lighting& l, const Vec3& n, const Vec3& toEye) {
  const float nl = std::max(n.dot(l.toLight), 0.0f);
  const Vec3 halfway = (l.toLight + toEye).normalized();
  const float nh = std::max(n.dot(halfway), 0.0f);
  Vec3 c = l.ambient * l.base + l.diffuse * nl * l.base +
           Vec3::Constant(l.specular * std::pow(nh, l.shininess));
  if (l.environment) {
    const Vec3 r = 2.0f * n.dot(toEye) * n - toEye;  // reflect(-toEye, n)
    const float up = std::clamp(r.y(), 0.0f, 1.0f);
    const Vec3 sky = (1.0f - up) * l.horizon + up * l.zenith;
    const float cosine = std::clamp(n.dot(toEye), 0.0f, 1.0f);
    const float fresnel = l.fresnelMin + (1.0f - l.fresnelMin) * std::pow(1.0f - cosine, 5.0f);
    c = (1.0f - fresnel) * c + fresnel * sky;
  }
  return c.cwiseMin(1.0f).cwiseMax(0.0f);
}

// sRGB encoding of a linear colour component, clamped to [0, 1] (the GL shaders encode the same
// way).
inline float toSrgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
inline std::uint8_t toSrgb8(float c) {
  return static_cast<std::uint8_t>(std::lround(255.0f * toSrgb(c)));
}

}  // namespace sph::render::frame
