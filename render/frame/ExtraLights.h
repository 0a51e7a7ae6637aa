// Lights that depend on the lit point's position (shaders/extra_lights.glsl): a system that has
// them (render/lights' particle-light volume) sets their uniforms and textures on each program
// that shades surfaces. Lighting::extra points to one, or is null and the hook adds nothing.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "render/gl/GlHandle.h"
#include "sim/Types.h"

namespace sph::render::frame {

struct Lighting;

// The deferred G-buffer read back for the CPU shading (render/frame/DeferredTarget.cpp), width x
// height pixels in GL's row order (row 0 at the bottom): the window depth (1 where nothing was
// drawn), and RGBA each the unit normal, the albedo (IEEE half floats, the target's own format)
// and the colour lit by all but these lights (linear). A pixel's world position is `position`'s
// (RGBA) where there is one (the frame has point splats, each lit at its centre), else found from
// its depth through `fromNdc`, the inverse of the frame's projection * view (column-major).
struct GBufferPixels {
  int width = 0, height = 0;
  const float* depth = nullptr;
  const float* normal = nullptr;
  const std::uint16_t* albedo = nullptr;
  const float* lit = nullptr;
  const float* position = nullptr;
  std::array<double, 16> fromNdc{};
  std::size_t count() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
};

class ExtraLights {
 public:
  virtual ~ExtraLights() = default;
  // Sets the hook's uniforms on `program` and binds what it samples (a GL context is current).
  virtual void apply(GLuint program) const = 0;
  // True: the lights are added in one full-screen pass over a G-buffer of the opaque surfaces
  // (render/frame/DeferredTarget.h) instead of in each surface's shader (lights.pipeline).
  virtual bool deferred() const { return false; }
  // Deferred only. True: each pixel's whole colour is computed on the CPU by shadeOnCpu from the
  // G-buffer read back, and the lighting pass copies it from a 2D texture instead of calling the
  // hook (lights.shade "cpu"; the lighting pass then never calls apply()).
  virtual bool shadesOnCpu() const { return false; }
  // Per pixel of `g` seen from `eye`, its lit colour plus the lights' term, clamped and
  // sRGB-encoded as shaders/deferred_lighting.frag does, into `rgba` (RGBA8, 4 g.count() bytes;
  // alpha 255 where a surface was drawn, all 0 elsewhere).
  virtual void shadeOnCpu(const GBufferPixels& /*g*/, const Vec3& /*eye*/,
                          std::uint8_t* /*rgba*/) const {}
};

// What every surface-shading program calls after its lighting uniforms: l.extra's, or the
// switches of shaders/extra_lights.glsl off.
void applyExtraLights(GLuint program, const Lighting& l);

}  // namespace sph::render::frame
