#include "render/splat/DeferredTarget.h"

#include <Eigen/Dense>

#include "render/gl/GlError.h"
#include "render/gl/Shader.h"
#include "render/splat/ExtraLights.h"
#include "render/splat/ProgramUniforms.h"

namespace sph::render::splat {

DeferredTarget::DeferredTarget(const gl::ShaderLibrary& shaders) {
  lighting_ = gl::buildProgram(shaders,
                               {{gl::ShaderStage::Vertex, "deferred_lighting.vert"},
                                {gl::ShaderStage::Fragment, "deferred_lighting.frag"}},
                               "deferred particle lighting");
  vao_ = gl::VertexArray::create();
}

void DeferredTarget::begin(int width, int height, bool water) {
  if (width != width_ || height != height_) {
    width_ = width, height_ = height;
    auto texture = [&](GLenum format) {
      gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
      glTextureStorage2D(t.id(), 1, format, width, height);
      return t;
    };
    // The lit colour in 32-bit float: RGBA16F's 2^-11 would cost a third of a step. The albedo
    // only scales the diffuse term: half floats are enough. The normal in 16-bit unorm (n / 2 +
    // 1/2: steps of 3e-5, a tenth of a half float's near 1; the two pipelines agree to one 8-bit
    // step, tests/test_lights.cpp, and a half-float normal moved sharp highlights by 2). The
    // position in float, for the water only; the solids' comes from the 32-bit depth.
    lit_ = texture(GL_RGBA32F);
    albedo_ = texture(GL_RGBA16F);
    normal_ = texture(GL_RGBA16);
    depth_ = texture(GL_DEPTH_COMPONENT32F);
    position_ = texture(GL_RGBA32F);
    framebuffer_ = gl::Framebuffer::create();
    const GLuint f = framebuffer_.id();
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT0, lit_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT1, albedo_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT2, normal_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT3, position_.id(), 0);
    glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                              GL_COLOR_ATTACHMENT3};
    glNamedFramebufferDrawBuffers(f, 4, buffers);
    if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw gl::GlError(
          "the deferred G-buffer (4 colour targets + depth) is incomplete on this driver");
  }
  // Without water the position target is not written at all (nor read: the lighting pass reads
  // it only where the water's flag is set).
  const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                            water ? GLenum{GL_COLOR_ATTACHMENT3} : GLenum{GL_NONE}};
  glNamedFramebufferDrawBuffers(framebuffer_.id(), 4, buffers);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, zero);  // coverage 0
  glClearNamedFramebufferfi(framebuffer_.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
}

void DeferredTarget::light(GLuint framebuffer, const ExtraLights& lights,
                           const CameraFrame& camera) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  const GLuint p = lighting_.id();
  lights.apply(p);
  setVec3(p, "u_eye", camera.eye);
  // Inverted in double: the far solids' depths lie within 1% of 1, and their positions come from
  // the difference.
  const Eigen::Matrix4d inverse =
      Eigen::Map<const Eigen::Matrix4f>(camera.projView.m.data()).cast<double>().inverse();
  const Eigen::Matrix4f inverseF = inverse.cast<float>();
  glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "u_inverseProjView"), 1, GL_FALSE,
                            inverseF.data());
  glProgramUniform2f(p, glGetUniformLocation(p, "u_pixelSize"), 2.0f / static_cast<float>(width_),
                     2.0f / static_cast<float>(height_));
  GLuint unit = 0;
  for (const gl::Texture* t : {&lit_, &albedo_, &normal_, &depth_, &position_})
    glBindTextureUnit(unit++, t->id());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);  // the G-buffer's depth is the frame's: written as it is
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glUseProgram(p);
  glBindVertexArray(vao_.id());  // no attributes: the triangle comes from gl_VertexID
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glDepthFunc(GL_LESS);
  for (GLuint u = 0; u < 5; ++u) glBindTextureUnit(u, 0);
}

}  // namespace sph::render::splat
