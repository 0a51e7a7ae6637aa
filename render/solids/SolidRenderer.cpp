#include "render/solids/SolidRenderer.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "render/frame/LightingUniforms.h"
#include "render/frame/ProgramUniforms.h"
#include "render/gl/Shader.h"
#include "render/solids/DrawOrder.h"

namespace sph::render::solids {

SolidRenderer::SolidRenderer(const std::vector<scene::BoundaryShape>& shapes, const Aabb& domain,
                             float thickness, const gl::ShaderLibrary& shaders)
    : shaders_(shaders),
      shapes_(shapes),
      domain_(domain),
      thickness_(thickness),
      segments_(shapes.size(), -1) {
  vertices_ = gl::Buffer::create();
  indices_ = gl::Buffer::create();
  vao_ = gl::VertexArray::create();
  const GLuint vao = vao_.id();
  glVertexArrayVertexBuffer(vao, 0, vertices_.id(), 0, sizeof(SolidVertex));
  for (GLuint a = 0; a < 2; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(
        vao, a, 3, GL_FLOAT, GL_FALSE,
        a == 0 ? offsetof(SolidVertex, position) : offsetof(SolidVertex, normal));
    glVertexArrayAttribBinding(vao, a, 0);
  }
  glVertexArrayElementBuffer(vao, indices_.id());
}

void SolidRenderer::fit(const scene::Mat4& projView) {
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  bool changed = false;
  for (std::size_t i = 0; i < shapes_.size(); ++i) {
    const int n =
        screenSegments(shapes_[i], thickness_, projView, viewport[2], viewport[3], tessellation);
    changed |= n != segments_[i];
    segments_[i] = n;
  }
  if (!changed) return;
  SolidMesh mesh;
  first_.resize(shapes_.size()), count_.resize(shapes_.size());
  for (std::size_t i = 0; i < shapes_.size(); ++i) {
    first_[i] = mesh.indices.size();
    mesh.append(tessellate(shapes_[i], domain_, thickness_, std::max(segments_[i], 4)));
    count_[i] = mesh.indices.size() - first_[i];
  }
  indexCount_ = mesh.indices.size();
  ++meshBuilds_;
  if (indexCount_ == 0) return;
  glNamedBufferData(vertices_.id(),
                    static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(SolidVertex)),
                    mesh.vertices.data(), GL_STATIC_DRAW);
  glNamedBufferData(indices_.id(),
                    static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                    mesh.indices.data(), GL_STATIC_DRAW);
}

void SolidRenderer::setLighting(GLuint p, const scene::CameraFrame& camera,
                                const frame::Lighting& lighting) const {
  frame::setVec3(p, "u_eye", camera.eye);
  // The scene's light, the solids' own material; no sky reflection (they are not water).
  frame::Lighting solid = lighting;
  solid.base = material.colour;
  solid.ambient = material.ambient, solid.diffuse = material.diffuse;
  solid.specular = material.specular, solid.shininess = material.shininess;
  solid.environment = false;
  frame::setLightingUniforms(p, solid);
}

GLuint SolidRenderer::program(Pass pass, const frame::Lighting& lighting) {
  const bool spotlight = lighting.spotlight.has_value();
  gl::Program& p = programs_[static_cast<int>(pass)][spotlight ? 1 : 0];
  if (p.id() != 0) return p.id();
  // The solids never reflect the sky (u_environment 0), and most frames have no rain spotlight:
  // llvmpipe runs a branch a uniform switches off for every pixel, so they are left out of the
  // program rather than switched off - about half of Fig. 11's G-buffer pass (docs/lights.md).
  std::vector<std::string> defines = {"SPH_NO_ENVIRONMENT"};
  if (!spotlight) defines.push_back("SPH_NO_SPOTLIGHT");
  if (pass != Pass::Lit) defines.push_back("SPH_NO_PARTICLE_LIGHTS");
  if (pass == Pass::GBuffer) defines.push_back("SPH_GBUFFER");
  static const char* const names[] = {"solids", "solids with particle lights",
                                      "solids into the G-buffer"};
  p = gl::buildProgram(
      shaders_,
      {{gl::ShaderStage::Vertex, "solid.vert"}, {gl::ShaderStage::Fragment, "solid.frag"}},
      names[static_cast<int>(pass)], defines);
  return p.id();
}

void SolidRenderer::draw(const scene::CameraFrame& camera, const frame::Lighting& lighting) {
  if (shapes_.empty()) return;
  const GLuint p = program(lighting.extra != nullptr ? Pass::Lit : Pass::Plain, lighting);
  setLighting(p, camera, lighting);
  drawWith(p, camera);
}

bool SolidRenderer::drawGBuffer(const scene::CameraFrame& camera, const frame::Lighting& lighting) {
  if (shapes_.empty()) return true;
  const GLuint p = program(Pass::GBuffer, lighting);
  setLighting(p, camera, lighting);
  drawWith(p, camera);
  return true;
}

void SolidRenderer::drawWith(GLuint p, const scene::CameraFrame& camera) {
  fit(camera.projView);
  if (indexCount_ == 0) return;
  glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "u_projView"), 1, GL_FALSE,
                            camera.projView.m.data());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glEnable(GL_CULL_FACE);  // the faces turned away: a tank's near walls, a sphere's far side
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glUseProgram(p);
  glBindVertexArray(vao_.id());
  if (!frontToBack) {
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indexCount_), GL_UNSIGNED_INT, nullptr);
  } else {
    // Each shape's triangles, nearest shape first (DrawOrder.h), in one call.
    drawCounts_.clear(), drawOffsets_.clear();
    solids::frontToBack(shapes_, thickness_, camera.eye, drawOrder_, drawDistance_);
    for (std::size_t i : drawOrder_) {
      if (count_[i] == 0) continue;
      drawCounts_.push_back(static_cast<GLsizei>(count_[i]));
      drawOffsets_.push_back(reinterpret_cast<const void*>(first_[i] * sizeof(std::uint32_t)));
    }
    glMultiDrawElements(GL_TRIANGLES, drawCounts_.data(), GL_UNSIGNED_INT, drawOffsets_.data(),
                        static_cast<GLsizei>(drawCounts_.size()));
  }
  glBindVertexArray(0);
  glDisable(GL_CULL_FACE);
  glUseProgram(0);
}

}  // namespace sph::render::solids
