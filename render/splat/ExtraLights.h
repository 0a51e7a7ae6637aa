// Lights that depend on the lit point's position (shaders/extra_lights.glsl): a system that has
// them (render/lights' particle-light volume) sets their uniforms and textures on each program
// that shades surfaces. Lighting::extra points to one, or is null and the hook adds nothing.
#pragma once

#include <cstddef>
#include <cstdint>

#include "render/gl/GlHandle.h"
#include "sim/Types.h"

namespace sph::render::splat {

struct Lighting;

// The deferred G-buffer read back (render/splat/DeferredTarget.cpp), `count` pixels in GL's row
// order, RGBA each: world position (alpha 1 where a surface was drawn), unit normal, albedo (IEEE
// half floats, the target's own format).
struct GBufferPixels {
  std::size_t count = 0;
  const float* position = nullptr;
  const float* normal = nullptr;
  const std::uint16_t* albedo = nullptr;
};

class ExtraLights {
 public:
  virtual ~ExtraLights() = default;
  // Sets the hook's uniforms on `program` and binds what it samples (a GL context is current).
  virtual void apply(GLuint program) const = 0;
  // True: the lights are added in one full-screen pass over a G-buffer of the opaque surfaces
  // (render/splat/DeferredTarget.h) instead of in each surface's shader (lights.pipeline).
  virtual bool deferred() const { return false; }
  // Deferred only. True: the lights' term is computed per pixel on the CPU by shadeOnCpu from the
  // G-buffer read back, and the lighting pass adds it from a 2D texture instead of calling the
  // hook (lights.shade "cpu"; the lighting pass then never calls apply()).
  virtual bool shadesOnCpu() const { return false; }
  // The term per pixel of `g` seen from `eye`, RGBA (alpha unused) into `rgba` (4 g.count floats).
  virtual void shadeOnCpu(const GBufferPixels& /*g*/, const Vec3& /*eye*/, float* /*rgba*/) const {}
};

// What every surface-shading program calls after its lighting uniforms: l.extra's, or the
// switches of shaders/extra_lights.glsl off.
void applyExtraLights(GLuint program, const Lighting& l);

}  // namespace sph::render::splat
