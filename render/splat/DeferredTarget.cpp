#include "render/splat/DeferredTarget.h"

#include <chrono>

#include "render/gl/GlError.h"
#include "render/gl/Shader.h"
#include "render/splat/ExtraLights.h"
#include "render/splat/ProgramUniforms.h"

namespace sph::render::splat {

DeferredTarget::DeferredTarget(const gl::ShaderLibrary& shaders) : shaders_(shaders) {
  lighting_ = gl::buildProgram(shaders,
                               {{gl::ShaderStage::Vertex, "deferred_lighting.vert"},
                                {gl::ShaderStage::Fragment, "deferred_lighting.frag"}},
                               "deferred particle lighting");
  vao_ = gl::VertexArray::create();
}

void DeferredTarget::begin(int width, int height) {
  if (width != width_ || height != height_) {
    width_ = width, height_ = height;
    auto texture = [&](GLenum format) {
      gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
      glTextureStorage2D(t.id(), 1, format, width, height);
      return t;
    };
    // 32-bit float position and normal: the lighting pass must see what the forward shader saw
    // (the two pipelines agree to one 8-bit step, tests/test_lights.cpp; a half-float normal moved
    // sharp highlights by 2 steps). The lit colour in float too: RGBA16F's 2^-11 would cost a
    // third of a step. The albedo only scales the diffuse term: half floats are enough.
    lit_ = texture(GL_RGBA32F);
    albedo_ = texture(GL_RGBA16F);
    position_ = texture(GL_RGBA32F);
    normal_ = texture(GL_RGBA32F);
    depth_ = texture(GL_DEPTH_COMPONENT32F);
    particle_ = gl::Texture{};  // made for lights.shade "cpu" only
    framebuffer_ = gl::Framebuffer::create();
    const GLuint f = framebuffer_.id();
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT0, lit_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT1, albedo_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT2, position_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT3, normal_.id(), 0);
    glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                              GL_COLOR_ATTACHMENT3};
    glNamedFramebufferDrawBuffers(f, 4, buffers);
    if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw gl::GlError(
          "the deferred G-buffer (4 float targets + depth) is incomplete on this driver");
  }
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, zero);
  // The position's alpha says "a surface here" to the CPU shading (lights.shade "cpu"): without
  // the clear it kept every earlier frame's surfaces, shaded for nothing as the camera moved.
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 2, zero);
  glClearNamedFramebufferfi(framebuffer_.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
}

void DeferredTarget::shadeOnCpu(const ExtraLights& lights, const Vec3& eye) {
  if (cpuLighting_.id() == 0) {
    cpuLighting_ = gl::buildProgram(shaders_,
                                    {{gl::ShaderStage::Vertex, "deferred_lighting.vert"},
                                     {gl::ShaderStage::Fragment, "deferred_lighting.frag"}},
                                    "deferred lighting, particle lights shaded on the CPU",
                                    {"SPH_CPU_PARTICLE_LIGHTS"});
  }
  if (particle_.id() == 0) {
    particle_ = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(particle_.id(), 1, GL_RGBA32F, width_, height_);
  }
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  readPosition_.resize(4 * n), readNormal_.resize(4 * n), readAlbedo_.resize(4 * n);
  term_.resize(4 * n);
  // In the targets' own formats: on llvmpipe a copy without conversion.
  glGetTextureImage(position_.id(), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(readPosition_.size() * sizeof(float)),
                    readPosition_.data());
  glGetTextureImage(normal_.id(), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(readNormal_.size() * sizeof(float)), readNormal_.data());
  glGetTextureImage(albedo_.id(), 0, GL_RGBA, GL_HALF_FLOAT,
                    static_cast<GLsizei>(readAlbedo_.size() * sizeof(std::uint16_t)),
                    readAlbedo_.data());
  lights.shadeOnCpu({n, readPosition_.data(), readNormal_.data(), readAlbedo_.data()}, eye,
                    term_.data());
  // RGBA32F: the term as the GL pass computes it, in float (the two agree to one 8-bit step).
  glTextureSubImage2D(particle_.id(), 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT, term_.data());
}

double DeferredTarget::light(GLuint framebuffer, const ExtraLights& lights, const Vec3& eye) {
  const auto start = std::chrono::steady_clock::now();
  const bool cpu = lights.shadesOnCpu();
  if (cpu) shadeOnCpu(lights, eye);
  const double seconds =
      cpu ? std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() : 0.0;
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  const GLuint p = cpu ? cpuLighting_.id() : lighting_.id();
  if (!cpu) lights.apply(p);
  setVec3(p, "u_eye", eye);
  GLuint unit = 0;
  for (const gl::Texture* t : {&lit_, &albedo_, &position_, &normal_, &depth_})
    glBindTextureUnit(unit++, t->id());
  if (cpu) glBindTextureUnit(5, particle_.id());
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
  for (GLuint u = 0; u < 6; ++u) glBindTextureUnit(u, 0);
  return seconds;
}

}  // namespace sph::render::splat
