// Lights that depend on the lit point's position (shaders/extra_lights.glsl): a system that has
// them (render/lights' particle-light volume) sets their uniforms and textures on each program
// that shades surfaces. Lighting::extra points to one, or is null and the hook adds nothing.
#pragma once

#include "render/gl/GlHandle.h"

namespace sph::render::splat {

struct Lighting;

class ExtraLights {
 public:
  virtual ~ExtraLights() = default;
  // Sets the hook's uniforms on `program` and binds what it samples (a GL context is current).
  virtual void apply(GLuint program) const = 0;
  // True: the lights are added in one full-screen pass over a G-buffer of the opaque surfaces
  // (render/splat/DeferredTarget.h) instead of in each surface's shader (lights.pipeline).
  virtual bool deferred() const { return false; }
};

// What every surface-shading program calls after its lighting uniforms: l.extra's, or the
// switches of shaders/extra_lights.glsl off.
void applyExtraLights(GLuint program, const Lighting& l);

}  // namespace sph::render::splat
