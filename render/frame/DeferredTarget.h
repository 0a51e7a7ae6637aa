// The deferred pipeline of the particle lights (lights.pipeline "deferred"; seed 004 Fig. 11;
// docs/lights.md, "Deferred"): a G-buffer of the frame's opaque surfaces (shaders/gbuffer_out.glsl:
// their colour lit by all but the particle lights, albedo, world position, normal, depth), then one
// full-screen pass (shaders/deferred_lighting.frag) that adds the particle lights' Phong terms
// once per pixel instead of once per fragment drawn. Exists only when a scene's lights are
// deferred (ExtraLights::deferred()); SplatRenderer makes it on first use. Needs a current context.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "render/gl/GlHandle.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/ShaderLibrary.h"
#include "sim/Types.h"
#include "sim/scene/Camera.h"

namespace sph::render::frame {

class ExtraLights;

class DeferredTarget {
 public:
  explicit DeferredTarget(const gl::ShaderLibrary& shaders);
  // Makes the G-buffer width x height (kept while the size stays), binds it as the draw
  // framebuffer and clears it (nothing drawn, depth 1). `cpu`: lights.shade "cpu", whose CPU pass
  // finds a surface where the depth is below 1 and a pixel's position from its depth: neither the
  // lit target is cleared (the GL pass's "alpha 1: a surface") nor the position target drawn,
  // unless `points` (point splats: their pixels all take their centre's position). The position
  // target is never cleared: a pixel holds a surface where its depth is below 1, and such a
  // pixel's position was written this frame.
  void begin(int width, int height, bool cpu, bool points);
  // The framebuffer the lighting pass draws into and what it needs there beyond the colour.
  struct Output {
    GLuint framebuffer = 0;  // 0: the window's; its viewport set
    bool normals = false;    // its second target takes the water's normals (the error figures')
    bool depth = true;       // something drawn after this pass is depth tested against the frame
    // Its colour where no surface is: the clear colour, sRGB-encoded (this pass is the first
    // thing drawn into it after its clear).
    std::array<std::uint8_t, 3> background{};
  };
  // Draws the lighting pass into out.framebuffer: every pixel the G-buffer holds a surface gets
  // its colour and depth; the others keep theirs.
  // Where lights.shadesOnCpu(), first reads the G-buffer back, has each pixel's colour computed on
  // the CPU and uploads it (lights.shade "cpu"; the pass then copies it); returns the seconds that
  // took (0 otherwise). Then, where neither out.normals nor out.depth is wanted, the copy is a
  // blit of the whole image, the pixels without a surface set to out.background on the CPU: no
  // full-screen pass, no depth written (docs/lights.md, "Shading on the CPU"); only where the
  // viewport is the whole target (0, 0, width, height), else the pass runs. `projView`: the
  // frame's.
  double light(const Output& out, const ExtraLights& lights, const Vec3& eye,
               const scene::Mat4& projView);

 private:
  const gl::ShaderLibrary& shaders_;
  gl::Program lighting_;
  gl::Program cpuLighting_;  // SPH_CPU_PARTICLE_LIGHTS, built on first use
  gl::Framebuffer framebuffer_;
  gl::VertexArray vao_;
  gl::Texture lit_, albedo_, position_, normal_, depth_;
  gl::ImageBlit final_;  // lights.shade "cpu": each pixel's colour, RGBA8 sRGB-encoded
  // The G-buffer read back and the colours computed from it, kept between frames.
  std::vector<float> readDepth_, readPosition_, readNormal_, readLit_;
  std::vector<std::uint16_t> readAlbedo_;
  std::vector<std::uint8_t> colours_;
  // Reads the G-buffer back, computes each pixel's colour on the CPU and uploads it into final_;
  // `background` (RGB, null: left 0) where no surface is.
  void shadeOnCpu(const ExtraLights& lights, const Vec3& eye, const scene::Mat4& projView,
                  const std::uint8_t* background);
  int width_ = 0, height_ = 0;
  int drawsPosition_ = -1;  // this frame's draw buffers: 1 with the position target, 0 without
};

}  // namespace sph::render::frame
