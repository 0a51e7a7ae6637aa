#include "render/splat/FrameRenderer.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "render/splat/ReferenceRaymarcher.h"

namespace sph::render::splat {

SplatParams splatParams(const scene::RenderDesc& d) {
  SplatParams p;
  p.kernelRadius = d.kernelRadius;
  p.surfaceThreshold = d.surfaceThreshold;
  p.splatSize = d.splatSize;
  p.perVertexDensity = d.perVertexDensity;
  p.projection = d.projection;
  p.translucent = d.alpha < 1.0f;
  p.cullBackFacing = d.cullBackFaces;
  return p;
}

frame::Lighting lighting(const scene::RenderDesc& d) {
  frame::Lighting l;
  l.environment = d.environment;
  l.alpha = d.alpha;
  return l;
}

scene::CameraDesc framingCamera(const Particles& p, float aspect) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (std::size_t i = 0; i < p.size(); ++i)
    lo = lo.cwiseMin(p.position(i)), hi = hi.cwiseMax(p.position(i));
  if (p.empty()) lo = hi = Vec3::Zero();
  scene::CameraDesc c;
  c.target = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * (hi - lo).norm(), 1e-3f);
  c.fovYDegrees = 40;
  const float fov =
      std::min(c.fovYDegrees, c.fovYDegrees * aspect) * static_cast<float>(solver::kPi) / 180.0f;
  const float distance = radius / std::sin(0.5f * fov) * 1.05f;
  c.position = c.target + distance * Vec3(0.55f, 0.45f, 0.7f).normalized();
  c.near = std::max(1e-4f, distance - 2 * radius);
  c.far = distance + 2 * radius;
  return c;
}

FrameRenderer::FrameRenderer(const scene::RenderDesc& desc, float spacing, float restDensity,
                             const gl::ShaderLibrary& shaders)
    : desc_(desc),
      spacing_(spacing),
      restDensity_(restDensity),
      params_(splatParams(desc)),
      lighting_(lighting(desc)),
      renderer_(desc.width, desc.height, shaders) {}

void FrameRenderer::setBoundary(const std::vector<float>& x, const std::vector<float>& y,
                                const std::vector<float>& z) {
  std::vector<SplatVertex> points(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) points[i] = SplatVertex{{x[i], y[i], z[i]}, {0, 1, 0}};
  renderer_.setBoundary(std::move(points), 0.75f * spacing_);
}

void FrameRenderer::prepare(const Particles& p) {
  const auto start = std::chrono::steady_clock::now();
  field_.emplace(p.x.data(), p.y.data(), p.z.data(), p.size(), spacing_, params_.kernelRadius,
                 restDensity_);
  fieldSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

RenderedSplats FrameRenderer::render(SplatKind kind, const scene::CameraDesc& camera) {
  const SplatFrame splats = build(kind, camera);
  return result(splats, renderer_.render(splats, kind, camera, lighting_));
}

RenderedSplats FrameRenderer::renderScored(SplatKind kind, const scene::CameraDesc& camera) {
  const SplatFrame splats = build(kind, camera);
  // The first draw of a program compiles llvmpipe's shader variants for it (5-15 ms, once per
  // run): not part of a frame's time, so the timed draw is the second.
  renderer_.render(splats, kind, camera, lighting_);
  const double drawSeconds = renderer_.render(splats, kind, camera, lighting_).seconds;
  frame::RenderImage scored =
      renderer_.render(splats, kind, camera, lighting_, frame::ImageContents::ColourAndNormals);
  scored.seconds = drawSeconds;
  return result(splats, std::move(scored));
}

SplatFrame FrameRenderer::build(SplatKind kind, const scene::CameraDesc& camera) const {
  const scene::CameraFrame cf = cameraFrame(camera, static_cast<float>(desc_.width) / desc_.height);
  return buildSplats(*field_, params_, kind, cf.projView, cf.eye);
}

RenderedSplats FrameRenderer::result(const SplatFrame& splats, frame::RenderImage image) const {
  RenderedSplats out;
  out.image = std::move(image);
  out.timings.field = fieldSeconds_;
  out.timings.splats = splats.timings;
  out.timings.draw = out.image.seconds;
  out.particles = splats.particles, out.surface = splats.surface, out.splats = splats.splats();
  out.SD = splats.SD, out.ID = splats.ID;
  return out;
}

FrameTimings FrameRenderer::drawToScreen(SplatKind kind, const scene::CameraDesc& camera, int width,
                                         int height) {
  const scene::CameraFrame cf =
      cameraFrame(camera, static_cast<float>(width) / std::max(height, 1));
  const SplatFrame splats = buildSplats(*field_, params_, kind, cf.projView, cf.eye);
  FrameTimings t;
  t.field = fieldSeconds_;
  t.splats = splats.timings;
  const auto start = std::chrono::steady_clock::now();
  renderer_.drawToScreen(splats, kind, camera, lighting_, width, height);
  t.draw = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return t;
}

// The solids, drawn by GL as in the pictures, are what the reference's rays end on.
std::optional<Backdrop> FrameRenderer::backdrop(const scene::CameraDesc& camera,
                                                const frame::Lighting& lighting) {
  if (!renderer_.hasLayers(frame::FrameLayer::Order::BeforeSplats)) return std::nullopt;
  return renderer_.drawBackdrop(camera, lighting);
}

frame::RenderImage FrameRenderer::reference(const scene::CameraDesc& camera) {
  frame::Lighting opaque = lighting_;
  opaque.alpha = 1;
  const std::optional<Backdrop> b = backdrop(camera, opaque);
  return raymarchReference(*field_, surfaceDensity(*field_, params_.surfaceThreshold), camera,
                           desc_.width, desc_.height, opaque, b ? &*b : nullptr);
}

frame::RenderImage FrameRenderer::referenceOfEveryParticle(const scene::CameraDesc& camera) {
  frame::Lighting opaque = lighting_;
  opaque.alpha = 1;
  const std::optional<Backdrop> b = backdrop(camera, opaque);
  // A ball of the particle's volume, spacing^3.
  const float radius = std::cbrt(3.0f / (4.0f * static_cast<float>(solver::kPi))) * spacing_;
  return raytraceParticleBalls(*field_, radius, camera, desc_.width, desc_.height, opaque,
                               b ? &*b : nullptr);
}

}  // namespace sph::render::splat
