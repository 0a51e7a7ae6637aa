// The deferred pipeline of the particle lights (lights.pipeline "deferred"; seed 004 Fig. 11;
// docs/lights.md, "Deferred"): a G-buffer of the frame's opaque surfaces (shaders/gbuffer_out.glsl:
// their colour lit by all but the particle lights, albedo, world position, normal, depth), then one
// full-screen pass (shaders/deferred_lighting.frag) that adds the particle lights' Phong terms
// once per pixel instead of once per fragment drawn. Exists only when a scene's lights are
// deferred (ExtraLights::deferred()); SplatRenderer makes it on first use. Needs a current context.
#pragma once

#include <cstdint>
#include <vector>

#include "render/gl/GlHandle.h"
#include "render/gl/ShaderLibrary.h"
#include "sim/Types.h"

namespace sph::render::splat {

class ExtraLights;

class DeferredTarget {
 public:
  explicit DeferredTarget(const gl::ShaderLibrary& shaders);
  // Makes the G-buffer width x height (kept while the size stays), binds it as the draw
  // framebuffer and clears it (nothing drawn, depth 1).
  void begin(int width, int height);
  // Draws the lighting pass into `framebuffer` (0: the window's), whose viewport is set: every
  // pixel the G-buffer holds a surface gets its colour and depth; the others keep theirs.
  // Where lights.shadesOnCpu(), first reads the G-buffer back, has the lights' term computed on
  // the CPU and uploads it (lights.shade "cpu"); returns the seconds that took (0 otherwise).
  double light(GLuint framebuffer, const ExtraLights& lights, const Vec3& eye);

 private:
  const gl::ShaderLibrary& shaders_;
  gl::Program lighting_;
  gl::Program cpuLighting_;  // SPH_CPU_PARTICLE_LIGHTS, built on first use
  gl::Framebuffer framebuffer_;
  gl::VertexArray vao_;
  gl::Texture lit_, albedo_, position_, normal_, depth_;
  gl::Texture particle_;  // lights.shade "cpu": the term per pixel, RGBA32F
  // The G-buffer read back and the term computed from it, kept between frames.
  std::vector<float> readPosition_, readNormal_, term_;
  std::vector<std::uint16_t> readAlbedo_;
  // Reads the G-buffer back, computes the lights' term on the CPU and uploads it into particle_.
  void shadeOnCpu(const ExtraLights& lights, const Vec3& eye);
  int width_ = 0, height_ = 0;
};

}  // namespace sph::render::splat
