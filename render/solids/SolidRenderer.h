// Draws the scene's solids (render/solids/SolidMesh.h) opaque and lit, per pixel, with the
// renderers' one lighting model (render/splat/Lighting.h, shaders/splat_shading.glsl) and a
// material of their own, as a layer of the splat frame (render/splat/FrameLayer.h): depth
// tested and written before the splats, so water in a cup is hidden by its near wall and the
// floor of a tank is behind the water.
#pragma once

#include <vector>

#include "render/gl/GlHandle.h"
#include "render/gl/ShaderLibrary.h"
#include "render/solids/SolidMesh.h"
#include "render/splat/FrameLayer.h"
#include "sim/Scene.h"

namespace sph::render::solids {

struct SolidMaterial {
  Vec3 colour = Vec3(0.78f, 0.76f, 0.72f);  // linear RGB
  float ambient = 0.35f, diffuse = 0.65f, specular = 0.15f, shininess = 24.0f;
};

class SolidRenderer final : public splat::FrameLayer {
 public:
  // Tessellates `shapes` (walls `thickness` m thick) and uploads them. Needs a current context.
  SolidRenderer(const std::vector<BoundaryShape>& shapes, const Aabb& domain, float thickness,
                const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());
  Order order() const override { return Order::BeforeSplats; }
  void draw(const CameraFrame& camera, const splat::Lighting& lighting) override;
  // The deferred pipeline's G-buffer (lights.pipeline "deferred"): the same lighting less the
  // particle lights, with albedo, position and normal per pixel; its program is built on first use.
  bool drawGBuffer(const CameraFrame& camera, const splat::Lighting& lighting) override;

  // The same triangles with `program` (its vertex stage solid.vert: u_projView), depth tested,
  // into the current framebuffer: G-buffers (render/lights/LightComparison.h).
  void drawWith(GLuint program, const CameraFrame& camera) const;

  std::size_t triangles() const { return indexCount_ / 3; }
  SolidMaterial material;

 private:
  void setLighting(GLuint program, const CameraFrame& camera,
                   const splat::Lighting& lighting) const;
  gl::ShaderLibrary shaders_;
  // Without the particle lights' code (SPH_NO_PARTICLE_LIGHTS), as the splats' programs: llvmpipe
  // pays for the volume sampling behind a switch that is off (docs/benchmarks.md, "Particle
  // lights"). The lit program (forward) and the G-buffer's (deferred) are built on first use.
  gl::Program program_, litProgram_, gbufferProgram_;
  gl::Buffer vertices_, indices_;
  gl::VertexArray vao_;
  std::size_t indexCount_ = 0;
};

}  // namespace sph::render::solids
