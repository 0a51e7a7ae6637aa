#include "render/frame/DeferredTarget.h"

#include <Eigen/LU>
#include <array>
#include <chrono>
#include <cstring>

#include "render/frame/ExtraLights.h"
#include "render/frame/ProgramUniforms.h"
#include "render/gl/GlError.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/Shader.h"

namespace sph::render::frame {
namespace {

// projView's inverse, column-major, in double: the CPU shading's way from a pixel's depth back to
// the world.
std::array<double, 16> inverse(const scene::Mat4& m) {
  Eigen::Matrix4d a;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) a(r, c) = m(r, c);
  const Eigen::Matrix4d inv = a.inverse();
  std::array<double, 16> out{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(4 * c + r)] = inv(r, c);
  return out;
}

}  // namespace

DeferredTarget::DeferredTarget(const gl::ShaderLibrary& shaders) : shaders_(shaders) {
  lighting_ = gl::buildProgram(shaders,
                               {{gl::ShaderStage::Vertex, "deferred_lighting.vert"},
                                {gl::ShaderStage::Fragment, "deferred_lighting.frag"}},
                               "deferred particle lighting");
  vao_ = gl::VertexArray::create();
}

void DeferredTarget::begin(int width, int height, bool cpu, bool points) {
  const bool positions = !cpu || points;
  if (width != width_ || height != height_) {
    width_ = width, height_ = height;
    auto texture = [&](GLenum format) {
      gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
      glTextureStorage2D(t.id(), 1, format, width, height);
      return t;
    };
    // The lighting pass must see what the forward shader saw (the two pipelines agree to one
    // 8-bit step, tests/test_lights.cpp; a half-float normal, 2^-11 near 1, moved sharp
    // highlights by 2 steps): the normal in 16-bit signed normalised (steps of 2^-15, 16 times
    // finer), the lit colour - clamped to [0, 1] by every G-buffer program - in 16-bit
    // normalised (2^-16; RGBA16F's 2^-11 would cost a third of a step), half the bytes of the
    // 32-bit floats they were for llvmpipe to write and read back (read back as float: the CPU
    // shading sees the same values). The position in 32-bit float. The albedo only scales the
    // diffuse term: half floats are enough.
    lit_ = texture(GL_RGBA16);
    albedo_ = texture(GL_RGBA16F);
    position_ = texture(GL_RGBA32F);
    normal_ = texture(GL_RGBA16_SNORM);
    depth_ = texture(GL_DEPTH_COMPONENT32F);
    framebuffer_ = gl::Framebuffer::create();
    const GLuint f = framebuffer_.id();
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT0, lit_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT1, albedo_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT2, position_.id(), 0);
    glNamedFramebufferTexture(f, GL_COLOR_ATTACHMENT3, normal_.id(), 0);
    glNamedFramebufferTexture(f, GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    if (glCheckNamedFramebufferStatus(f, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw gl::GlError(
          "the deferred G-buffer (RGBA16, RGBA16F, RGBA32F, RGBA16_SNORM + 32-bit float depth) is "
          "incomplete on this driver");
    drawsPosition_ = -1;
  }
  // Without point splats the CPU shading reads the depth instead of the position: llvmpipe then
  // neither writes nor reads back 16 bytes a pixel.
  const GLuint f = framebuffer_.id();
  if (drawsPosition_ != (positions ? 1 : 0)) {
    drawsPosition_ = positions ? 1 : 0;
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1,
                              positions ? GLenum{GL_COLOR_ATTACHMENT2} : GLenum{GL_NONE},
                              GL_COLOR_ATTACHMENT3};
    glNamedFramebufferDrawBuffers(f, 4, buffers);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, f);
  // A surface is where lit's alpha is 1 (the GL lighting pass) or the depth is below 1 (the CPU
  // pass, which reads lit only there): cleared each frame, so no earlier frame's surface is
  // shaded as the camera moves; the position target needs no clear, nor lit on the CPU path.
  const float zero[4] = {0, 0, 0, 0};
  if (!cpu) glClearNamedFramebufferfv(f, GL_COLOR, 0, zero);
  glClearNamedFramebufferfi(f, GL_DEPTH_STENCIL, 0, 1.0f, 0);
}

void DeferredTarget::shadeOnCpu(const ExtraLights& lights, const Vec3& eye,
                                const scene::Mat4& projView, const std::uint8_t* background) {
  if (cpuLighting_.id() == 0) {
    cpuLighting_ = gl::buildProgram(shaders_,
                                    {{gl::ShaderStage::Vertex, "deferred_lighting.vert"},
                                     {gl::ShaderStage::Fragment, "deferred_lighting.frag"}},
                                    "deferred lighting, the colours shaded on the CPU",
                                    {"SPH_CPU_PARTICLE_LIGHTS"});
  }
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  readDepth_.resize(n), readNormal_.resize(4 * n), readAlbedo_.resize(4 * n),
      readLit_.resize(4 * n);
  colours_.resize(4 * n);
  // In the targets' own formats: on llvmpipe a copy without conversion.
  auto read = [](const gl::Texture& t, GLenum format, GLenum type, std::size_t bytes, void* to) {
    gl::readTexture(t.id(), format, type, bytes, to);
  };
  read(depth_, GL_DEPTH_COMPONENT, GL_FLOAT, n * sizeof(float), readDepth_.data());
  read(normal_, GL_RGBA, GL_FLOAT, 4 * n * sizeof(float), readNormal_.data());
  read(albedo_, GL_RGBA, GL_HALF_FLOAT, 4 * n * sizeof(std::uint16_t), readAlbedo_.data());
  read(lit_, GL_RGBA, GL_FLOAT, 4 * n * sizeof(float), readLit_.data());
  if (drawsPosition_ == 1) {
    readPosition_.resize(4 * n);
    read(position_, GL_RGBA, GL_FLOAT, 4 * n * sizeof(float), readPosition_.data());
  }
  GBufferPixels g;
  g.width = width_, g.height = height_;
  g.depth = readDepth_.data(), g.normal = readNormal_.data(), g.albedo = readAlbedo_.data();
  g.lit = readLit_.data();
  g.position = drawsPosition_ == 1 ? readPosition_.data() : nullptr;
  g.fromNdc = inverse(projView);
  lights.shadeOnCpu(g, eye, colours_.data());
  if (background) {
    // The blit copies every pixel: those without a surface (all 0) take the target's clear colour.
    std::uint32_t fill = 0xff000000u, *pixel = reinterpret_cast<std::uint32_t*>(colours_.data());
    std::memcpy(&fill, background, 3);
    for (std::size_t i = 0; i < n; ++i)
      if (pixel[i] == 0) pixel[i] = fill;
  }
  final_.upload(width_, height_, GL_RGBA, colours_.data());
}

double DeferredTarget::light(const Output& out, const ExtraLights& lights, const Vec3& eye,
                             const scene::Mat4& projView) {
  const auto start = std::chrono::steady_clock::now();
  const bool cpu = lights.shadesOnCpu();
  // The blit covers (0, 0, width, height) of the target: only where that is the viewport the pass
  // below would draw into (a caller drawing a panel of a larger frame gets the pass).
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  const bool whole =
      viewport[0] == 0 && viewport[1] == 0 && viewport[2] == width_ && viewport[3] == height_;
  const bool blit = cpu && !out.normals && !out.depth && whole;
  if (cpu) shadeOnCpu(lights, eye, projView, blit ? out.background.data() : nullptr);
  const double seconds =
      cpu ? std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() : 0.0;
  if (blit) {
    // Same size and format: llvmpipe copies the rows, where the pass below runs a fragment
    // program over every pixel to fetch the colour and the depth (5-6 ms of Fig. 11's 960 x 540,
    // docs/notes/2026-11-27-lights-fig11.md, "Fig. 11's G-buffer and copy made lighter").
    final_.blit(out.framebuffer, 0, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, out.framebuffer);
    return seconds;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, out.framebuffer);
  const GLuint p = cpu ? cpuLighting_.id() : lighting_.id();
  if (!cpu) lights.apply(p);
  setVec3(p, "u_eye", eye);
  setInt(p, "u_normals", out.normals ? 1 : 0);
  GLuint unit = 0;
  for (const gl::Texture* t : {&lit_, &albedo_, &position_, &normal_, &depth_})
    glBindTextureUnit(unit++, t->id());
  if (cpu) glBindTextureUnit(5, final_.texture());
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

}  // namespace sph::render::frame
