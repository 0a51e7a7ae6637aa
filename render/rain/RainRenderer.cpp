#include "render/rain/RainRenderer.h"

#include <vector>

#include "render/gl/Shader.h"
#include "render/rain/StreakImages.h"
#include "render/splat/ProgramUniforms.h"
#include "render/splat/SpotlightUniforms.h"

namespace sph::render::rain {
namespace {

constexpr int kStreakWidth = 16, kStreakHeight = 64;  // pixels of one streak image

}  // namespace

RainRenderer::RainRenderer(const RainDesc& desc, const gl::ShaderLibrary& shaders) : desc_(desc) {
  program_ = gl::buildProgram(
      shaders, {{gl::ShaderStage::Vertex, "rain.vert"}, {gl::ShaderStage::Fragment, "rain.frag"}},
      "rain");
  const StreakImages images =
      generateStreakImages(desc.streakLayers, kStreakWidth, kStreakHeight, desc.seed);
  streaks_ = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
  const GLuint t = streaks_.id();
  glTextureStorage3D(t, 1, GL_R8, images.width, images.height, images.layers);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage3D(t, 0, 0, 0, 0, images.width, images.height, images.layers, GL_RED,
                      GL_UNSIGNED_BYTE, images.alpha.data());
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  drops_ = gl::Buffer::create();
  vao_ = gl::VertexArray::create();
  const GLuint vao = vao_.id();
  glVertexArrayVertexBuffer(vao, 0, drops_.id(), 0, 4 * sizeof(float));
  glVertexArrayBindingDivisor(vao, 0, 1);  // one drop per instance
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
}

void RainRenderer::setDrops(const sph::rain::RainSystem& rain) {
  const std::vector<Vec3>& p = rain.positions();
  const std::vector<std::uint8_t>& layers = rain.layers();
  std::vector<float> packed(4 * p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    packed[4 * i] = p[i].x(), packed[4 * i + 1] = p[i].y(), packed[4 * i + 2] = p[i].z();
    packed[4 * i + 3] = layers[i];
  }
  count_ = p.size();
  velocity_ = rain.velocity();
  glNamedBufferData(drops_.id(), static_cast<GLsizeiptr>(packed.size() * sizeof(float)),
                    packed.data(), GL_STREAM_DRAW);
}

void RainRenderer::draw(const CameraFrame& camera, const splat::Lighting& lighting) {
  if (count_ == 0) return;
  const GLuint p = program_.id();
  glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "u_projView"), 1, GL_FALSE,
                            camera.projView.m.data());
  splat::setVec3(p, "u_eye", camera.eye);
  splat::setVec3(p, "u_right", camera.right);
  splat::setVec3(p, "u_velocity", velocity_);
  splat::setFloat(p, "u_exposure", desc_.exposure);
  splat::setFloat(p, "u_width", desc_.dropWidth);
  splat::setVec3(p, "u_unlit", kUnlitTint * lighting.background);
  splat::setSpotlightUniforms(p, desc_.spotlight);
  glProgramUniform1i(p, glGetUniformLocation(p, "u_streaks"), 0);
  glBindTextureUnit(0, streaks_.id());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDisable(GL_CULL_FACE);
  glUseProgram(p);
  glBindVertexArray(vao_.id());
  glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(count_));
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

}  // namespace sph::render::rain
