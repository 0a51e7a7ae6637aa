// One frame from particles to a picture, the way every command does it (`run` with a render
// section, `render`, `compare`, `view`): the density field of the particles, the splats of a
// kind, the GL draw; with the time of each part (seed 003's Table 1 counts all of them).
// Needs a current GL context.
#pragma once

#include <optional>

#include "render/frame/Lighting.h"
#include "render/frame/RenderImage.h"
#include "render/splat/DensityField.h"
#include "render/splat/SplatBuilder.h"
#include "render/splat/SplatRenderer.h"
#include "sim/Particles.h"
#include "sim/scene/CameraDesc.h"
#include "sim/scene/RenderDesc.h"

namespace sph::render::splat {

SplatParams splatParams(const scene::RenderDesc& desc);
frame::Lighting lighting(const scene::RenderDesc& desc);

// A camera that frames the particles' box from the front-right-above (for caches whose scene
// has no camera).
scene::CameraDesc framingCamera(const Particles& particles, float aspect);

struct FrameTimings {
  double field = 0;  // grid + particle densities (part of surface detection)
  SplatTimings splats;
  double draw = 0;  // upload + draw until finished
  double total() const { return field + splats.surface + splats.normals + splats.build + draw; }
};

struct RenderedSplats {
  frame::RenderImage image;
  FrameTimings timings;
  std::size_t particles = 0, surface = 0, splats = 0;  // splats drawn (SplatFrame::splats())
  float SD = 0, ID = 0;
};

class FrameRenderer {
 public:
  FrameRenderer(const scene::RenderDesc& desc, float spacing, float restDensity,
                const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());

  // Walls to show behind and around the fluid (boundary particle positions, m), translucent;
  // they do not enter the error figures. Empty vectors: none.
  void setBoundary(const std::vector<float>& x, const std::vector<float>& y,
                   const std::vector<float>& z);

  // Builds the field of `particles` (kept for the calls below until the next prepare()).
  void prepare(const Particles& particles);

  // Splats of `kind` for the prepared particles, drawn offscreen and read back (colour only: the
  // pictures `render` and `run` write).
  RenderedSplats render(SplatKind kind, const scene::CameraDesc& camera);
  // The same frame for the error figures: the image with its normals and coverage, and the
  // timings of render() with a warm draw (the splats are built once and drawn three times: to
  // compile shaders, timed as a picture, and with the normal target, which is not part of making
  // a picture and would cost llvmpipe ~3 ms of the draw).
  RenderedSplats renderScored(SplatKind kind, const scene::CameraDesc& camera);
  // The same into the current window's framebuffer.
  FrameTimings drawToScreen(SplatKind kind, const scene::CameraDesc& camera, int width, int height);
  // The reference ray-marched image of the same SD surface, with the solids (the layers drawn
  // before the splats) where the pictures have them.
  frame::RenderImage reference(const scene::CameraDesc& camera);
  // Every particle as a ball of its own volume (radius 0.62 spacings), ray-traced, with the same
  // solids: thin jets and lone drops whose D stays below SD, which the SD surface (and so the
  // reference) drops. For judging the splats' jets, not an error reference.
  frame::RenderImage referenceOfEveryParticle(const scene::CameraDesc& camera);

  // Layers drawn in every picture with the splats (render/frame/FrameLayer.h), not owned.
  void setLayers(std::vector<frame::FrameLayer*> layers) { renderer_.setLayers(std::move(layers)); }

  // Position-dependent lights for every surface drawn (render/frame/ExtraLights.h), not owned;
  // null: none.
  void setExtraLights(const frame::ExtraLights* extra) { lighting_.extra = extra; }
  // The colour of empty pixels (linear RGB).
  void setBackground(const Vec3& colour) { lighting_.background = colour; }
  // The rain's spotlight lights the water and solids of every picture (Lighting::spotlight).
  void setSpotlight(const std::optional<scene::SpotlightDesc>& light) {
    lighting_.spotlight = light;
  }

  const scene::RenderDesc& desc() const { return desc_; }
  float spacing() const { return spacing_; }  // m, the fluid's particle spacing

 private:
  SplatFrame build(SplatKind kind, const scene::CameraDesc& camera) const;
  RenderedSplats result(const SplatFrame& splats, frame::RenderImage image) const;
  std::optional<Backdrop> backdrop(const scene::CameraDesc& camera,
                                   const frame::Lighting& lighting);
  scene::RenderDesc desc_;
  float spacing_, restDensity_;
  SplatParams params_;
  frame::Lighting lighting_;
  SplatRenderer renderer_;
  std::optional<DensityField> field_;
  double fieldSeconds_ = 0;
};

}  // namespace sph::render::splat
