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
#include "sim/Camera.h"
#include "sim/Types.h"

namespace sph::render::splat {

class ExtraLights;

class DeferredTarget {
 public:
  explicit DeferredTarget(const gl::ShaderLibrary& shaders);
  // Makes the G-buffer width x height (kept while the size stays), binds it as the draw
  // framebuffer and clears it (nothing drawn, depth 1). `positions` false: the position target is
  // not drawn (the CPU shading then finds a pixel's position from its depth); it must be drawn for
  // the GL lighting pass and for point splats, whose pixels all take their centre's position. It
  // is never cleared: a pixel holds a surface where its depth is below 1 (lit's alpha is 1), and
  // such a pixel's position was written this frame.
  void begin(int width, int height, bool positions);
  // Draws the lighting pass into `framebuffer` (0: the window's), whose viewport is set: every
  // pixel the G-buffer holds a surface gets its colour and depth; the others keep theirs.
  // Where lights.shadesOnCpu(), first reads the G-buffer back, has each pixel's colour computed on
  // the CPU and uploads it (lights.shade "cpu"; the pass then copies it); returns the seconds that
  // took (0 otherwise). `projView`: the frame's. `normals`: the framebuffer's second target takes
  // the water's normals (the error figures' frame).
  double light(GLuint framebuffer, const ExtraLights& lights, const Vec3& eye, const Mat4& projView,
               bool normals);

 private:
  const gl::ShaderLibrary& shaders_;
  gl::Program lighting_;
  gl::Program cpuLighting_;  // SPH_CPU_PARTICLE_LIGHTS, built on first use
  gl::Framebuffer framebuffer_;
  gl::VertexArray vao_;
  gl::Texture lit_, albedo_, position_, normal_, depth_;
  gl::Texture final_;  // lights.shade "cpu": each pixel's colour, RGBA8 sRGB-encoded
  // The G-buffer read back and the colours computed from it, kept between frames.
  std::vector<float> readDepth_, readPosition_, readNormal_, readLit_;
  std::vector<std::uint16_t> readAlbedo_;
  std::vector<std::uint8_t> colours_;
  // Reads the G-buffer back, computes each pixel's colour on the CPU and uploads it into final_.
  void shadeOnCpu(const ExtraLights& lights, const Vec3& eye, const Mat4& projView);
  int width_ = 0, height_ = 0;
  int drawsPosition_ = -1;  // this frame's draw buffers: 1 with the position target, 0 without
};

}  // namespace sph::render::splat
