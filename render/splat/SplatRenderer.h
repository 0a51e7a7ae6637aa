// Draws a frame's splats with OpenGL into an offscreen framebuffer (colour, and on request the
// normal/coverage target of the error figures) and reads it back as a RenderImage. Needs a current
// context (render/gl/GlContext.h): headless for `sphsplat render` / `compare`, the window's for
// `sphsplat view` (drawToScreen).
#pragma once

#include <memory>
#include <vector>

#include "render/frame/FrameLayer.h"
#include "render/frame/Lighting.h"
#include "render/frame/RenderImage.h"
#include "render/gl/GlHandle.h"
#include "render/gl/ShaderLibrary.h"
#include "render/splat/ReferenceRaymarcher.h"
#include "render/splat/SplatBuilder.h"
#include "sim/scene/Camera.h"

namespace sph::render::frame {
class DeferredTarget;
}  // namespace sph::render::frame

namespace sph::render::splat {

class SplatRenderer {
 public:
  // Compiles the splat programs and makes a width x height framebuffer. Throws gl::ShaderError.
  SplatRenderer(int width, int height,
                const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());
  ~SplatRenderer();
  SplatRenderer(const SplatRenderer&) = delete;
  SplatRenderer& operator=(const SplatRenderer&) = delete;

  // Uploads and draws `frame` (its points or its quads) into the offscreen framebuffer and reads
  // it back. `seconds` of the result: upload + draw until finished (not the read-back).
  // ColourAndNormals also draws the normal/coverage target the error figures need (it costs
  // llvmpipe ~3 ms a frame at 960x540, so pictures are drawn without it).
  frame::RenderImage render(const SplatFrame& frame, SplatKind kind,
                            const scene::CameraDesc& camera, const frame::Lighting& lighting,
                            frame::ImageContents contents = frame::ImageContents::Colour);
  // The walls and containers, drawn after the fluid as translucent grey squares into the colour
  // only (the error figures see the fluid alone). Empty: none.
  void setBoundary(std::vector<SplatVertex> points, float halfSide);
  // Layers drawn in the same pictures: solids before the splats, rain after them. The error
  // figures' frame (ColourAndNormals) has the solids in its colour, hiding what they hide, and
  // no rain; its normal target is the water's alone. Not owned; they must outlive their use.
  void setLayers(std::vector<frame::FrameLayer*> layers) { layers_ = std::move(layers); }
  bool hasLayers(frame::FrameLayer::Order order) const;
  // The layers drawn before the splats (the solids) alone, with their depth: what the reference
  // ray-marcher shows behind and in front of the water.
  Backdrop drawBackdrop(const scene::CameraDesc& camera, const frame::Lighting& lighting);
  // Draws into the default framebuffer of the current (window) context instead.
  void drawToScreen(const SplatFrame& frame, SplatKind kind, const scene::CameraDesc& camera,
                    const frame::Lighting& lighting, int viewportWidth, int viewportHeight);

  // The last draw's deferred passes (lights.pipeline "deferred"; zero when forward), seconds:
  // the G-buffer of the opaque surfaces, each pixel's colour on the CPU (lights.shade "cpu":
  // read-back, shading, encoding and upload; zero on the GL path) and the full-screen lighting
  // pass, a copy after the CPU's (seed 004 Fig. 11).
  struct DrawPasses {
    double gbuffer = 0, particles = 0, lighting = 0;
  };
  const DrawPasses& lastPasses() const { return passes_; }

 private:
  double draw(const SplatFrame& frame, SplatKind kind, const scene::CameraDesc& camera,
              const frame::Lighting& lighting, int w, int h, bool offscreen);
  GLuint programFor(SplatKind kind, bool particleLights);
  GLuint gbufferProgramFor(SplatKind kind);
  void drawSplats(const SplatFrame& frame, SplatKind kind, const scene::CameraFrame& cam,
                  const frame::Lighting& lighting, GLuint program);
  void drawDeferred(const SplatFrame& frame, SplatKind kind, const scene::CameraFrame& cam,
                    const frame::Lighting& lighting, int w, int h, bool offscreen);
  int width_, height_;
  gl::ShaderLibrary shaders_;
  // Without the particle lights' code (SPH_NO_PARTICLE_LIGHTS): llvmpipe runs a vertex shader's
  // 3D-texture sampling even behind a uniform switch that is off, +50% draw time at 100k
  // particles (docs/notes/2026-11-23-splat-renderer.md). The lit ones are built for `lights` only.
  gl::Program pointProgram_, quadProgram_;
  gl::Program litPointProgram_, litQuadProgram_;
  // The deferred pipeline's G-buffer programs and target, made on its first frame.
  gl::Program gbufferPointProgram_, gbufferQuadProgram_;
  std::unique_ptr<frame::DeferredTarget> deferred_;
  DrawPasses passes_;
  gl::Framebuffer framebuffer_;
  gl::Texture colour_, normal_;
  gl::Renderbuffer depth_;
  gl::VertexArray pointVao_, quadVao_;
  gl::Buffer pointBuffer_, quadBuffer_, indexBuffer_, boundaryBuffer_;
  gl::VertexArray boundaryVao_;
  std::size_t boundaryCount_ = 0;
  float boundaryHalfSide_ = 0;
  void drawBoundary(bool offscreen);
  void drawLayers(frame::FrameLayer::Order order, const scene::CameraFrame& camera,
                  const frame::Lighting& lighting, bool offscreen);
  std::vector<frame::FrameLayer*> layers_;
  void selectDrawBuffers(frame::ImageContents contents);
  frame::ImageContents contents_ = frame::ImageContents::ColourAndNormals;
};

}  // namespace sph::render::splat
