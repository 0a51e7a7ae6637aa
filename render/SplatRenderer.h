// Draws a frame's splats with OpenGL into an offscreen framebuffer (colour, and on request the
// normal/coverage target of the error figures) and reads it back as a RenderImage. Needs a current
// context (render/GlContext.h): headless for `sphsplat render` / `compare`, the window's for
// `sphsplat view` (drawToScreen).
#pragma once

#include <vector>

#include "render/GlHandle.h"
#include "render/Lighting.h"
#include "render/RenderImage.h"
#include "render/ShaderLibrary.h"
#include "render/SplatBuilder.h"
#include "sim/CameraDesc.h"

namespace sph::render {

// The matrices and basis of a camera for a viewport aspect ratio.
struct CameraFrame {
  cdt::Mat4 projView;
  Vec3 eye, right, up;
};
CameraFrame cameraFrame(const CameraDesc& camera, float aspect);

class SplatRenderer {
 public:
  // Compiles the splat programs and makes a width x height framebuffer. Throws ShaderError.
  SplatRenderer(int width, int height,
                const ShaderLibrary& shaders = ShaderLibrary::fromEnvironment());
  ~SplatRenderer();
  SplatRenderer(const SplatRenderer&) = delete;
  SplatRenderer& operator=(const SplatRenderer&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

  // Uploads and draws `frame` (its points or its quads) into the offscreen framebuffer and reads
  // it back. `seconds` of the result: upload + draw until finished (not the read-back).
  // ColourAndNormals also draws the normal/coverage target the error figures need (it costs
  // llvmpipe ~3 ms a frame at 960x540, so pictures are drawn without it).
  RenderImage render(const SplatFrame& frame, SplatKind kind, const CameraDesc& camera,
                     const Lighting& lighting, ImageContents contents = ImageContents::Colour);
  // The walls and containers, drawn after the fluid as translucent grey squares into the colour
  // only (the error figures see the fluid alone). Empty: none.
  void setBoundary(std::vector<SplatVertex> points, float halfSide);
  // Draws into the default framebuffer of the current (window) context instead.
  void drawToScreen(const SplatFrame& frame, SplatKind kind, const CameraDesc& camera,
                    const Lighting& lighting, int viewportWidth, int viewportHeight);

 private:
  double draw(const SplatFrame& frame, SplatKind kind, const CameraDesc& camera,
              const Lighting& lighting, int w, int h, bool offscreen);
  int width_, height_;
  Program pointProgram_, quadProgram_;
  Framebuffer framebuffer_;
  Texture colour_, normal_;
  Renderbuffer depth_;
  VertexArray pointVao_, quadVao_;
  Buffer pointBuffer_, quadBuffer_, indexBuffer_, boundaryBuffer_;
  VertexArray boundaryVao_;
  std::size_t boundaryCount_ = 0;
  float boundaryHalfSide_ = 0;
  void drawBoundary(bool offscreen);
  void selectDrawBuffers(ImageContents contents);
  ImageContents contents_ = ImageContents::ColourAndNormals;
};

}  // namespace sph::render
