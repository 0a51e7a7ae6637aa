// Draws the scene's solids (render/solids/SolidMesh.h) opaque and lit, per pixel, with the
// renderers' one lighting model (render/frame/Lighting.h, shaders/splat_shading.glsl) and a
// material of their own, as a layer of the splat frame (render/frame/FrameLayer.h): depth
// tested and written before the splats, so water in a cup is hidden by its near wall and the
// floor of a tank is behind the water.
#pragma once

#include <vector>

#include "render/frame/FrameLayer.h"
#include "render/gl/GlHandle.h"
#include "render/gl/ShaderLibrary.h"
#include "render/solids/ScreenTessellation.h"
#include "render/solids/SolidMesh.h"
#include "sim/scene/Scene.h"

namespace sph::render::solids {

struct SolidMaterial {
  Vec3 colour = Vec3(0.78f, 0.76f, 0.72f);  // linear RGB
  float ambient = 0.35f, diffuse = 0.65f, specular = 0.15f, shininess = 24.0f;
};

class SolidRenderer final : public frame::FrameLayer {
 public:
  // Keeps `shapes` (walls `thickness` m thick) to tessellate for each draw's camera and viewport
  // (`tessellation`). Needs a current context.
  SolidRenderer(const std::vector<scene::BoundaryShape>& shapes, const Aabb& domain,
                float thickness,
                const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());
  Order order() const override { return Order::BeforeSplats; }
  void draw(const scene::CameraFrame& camera, const frame::Lighting& lighting) override;
  // The deferred pipeline's G-buffer (lights.pipeline "deferred"): the same lighting less the
  // particle lights, with albedo, position and normal per pixel; its program is built on first use.
  bool drawGBuffer(const scene::CameraFrame& camera, const frame::Lighting& lighting) override;

  // The same triangles with `program` (its vertex stage solid.vert: u_projView), depth tested,
  // into the current framebuffer and viewport: G-buffers (render/lights/LightComparison.h).
  void drawWith(GLuint program, const scene::CameraFrame& camera);

  // The triangles of the last draw (0 before the first).
  std::size_t triangles() const { return indexCount_ / 3; }
  // The segments the last draw tessellated each shape with, in the order given (0: a shape with
  // no curve).
  const std::vector<int>& segments() const { return segments_; }
  // How many times the mesh was built and uploaded: once, then once per change of segments.
  std::size_t meshBuilds() const { return meshBuilds_; }
  SolidMaterial material;
  // How finely the spheres and cups are tessellated for their size on screen
  // (ScreenTessellation.h); floor = cap = 64 is the fixed tessellation of before.
  TessellationBound tessellation;
  // Nearest shape first (DrawOrder.h): the same picture, less shading hidden behind; false draws
  // them in the order given.
  bool frontToBack = true;

 private:
  void setLighting(GLuint program, const scene::CameraFrame& camera,
                   const frame::Lighting& lighting) const;
  // Tessellates the shapes for `projView` in the current viewport where a shape's segments
  // change, and uploads the mesh; nothing (no allocation) while they stay.
  void fit(const scene::Mat4& projView);
  gl::ShaderLibrary shaders_;
  std::vector<scene::BoundaryShape> shapes_;
  Aabb domain_;
  float thickness_;
  std::vector<int> segments_;  // per shape, what the buffers hold; -1 before the first draw
  // Forward without the particle lights, forward with them, the deferred G-buffer's.
  enum class Pass { Plain, Lit, GBuffer };
  // The pass's program for a frame with or without the rain's spotlight, built on first use.
  // Code behind a switch that is off is left out (SPH_NO_PARTICLE_LIGHTS but for Lit, as the
  // splats' programs; SPH_NO_ENVIRONMENT; SPH_NO_SPOTLIGHT): llvmpipe pays for it otherwise
  // (docs/benchmarks.md, "Particle lights").
  GLuint program(Pass pass, const frame::Lighting& lighting);
  gl::Program programs_[3][2];  // [pass][spotlight]
  gl::Buffer vertices_, indices_;
  gl::VertexArray vao_;
  std::size_t indexCount_ = 0, meshBuilds_ = 0;
  std::vector<std::size_t> first_, count_;  // per shape, its triangles' indices in indices_
  std::vector<std::size_t> drawOrder_;      // the draw's, kept between draws
  std::vector<float> drawDistance_;
  std::vector<GLsizei> drawCounts_;
  std::vector<const void*> drawOffsets_;
};

}  // namespace sph::render::solids
