// The deferred pipeline of the particle lights (lights.pipeline "deferred"; seed 004 Fig. 11;
// docs/lights.md, "Deferred"): a G-buffer of the frame's opaque surfaces (shaders/gbuffer_out.glsl:
// their colour lit by all but the particle lights, albedo, world position, normal, depth), then one
// full-screen pass (shaders/deferred_lighting.frag) that adds the particle lights' Phong terms
// once per pixel instead of once per fragment drawn. Exists only when a scene's lights are
// deferred (ExtraLights::deferred()); SplatRenderer makes it on first use. Needs a current context.
#pragma once

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
  void light(GLuint framebuffer, const ExtraLights& lights, const Vec3& eye);

 private:
  gl::Program lighting_;
  gl::Framebuffer framebuffer_;
  gl::VertexArray vao_;
  gl::Texture lit_, albedo_, position_, normal_, depth_;
  int width_ = 0, height_ = 0;
};

}  // namespace sph::render::splat
