#include "render/rain/RainRenderer.h"

#include <algorithm>
#include <vector>

#include "render/frame/ProgramUniforms.h"
#include "render/frame/SpotlightUniforms.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/Shader.h"
#include "render/rain/ComposeOver.h"
#include "render/rain/StreakImages.h"

namespace sph::render::rain {
namespace {

constexpr int kStreakWidth = 16, kStreakHeight = 64;  // pixels of one streak image

}  // namespace

RainRenderer::RainRenderer(const scene::RainDesc& desc, const gl::ShaderLibrary& shaders)
    : desc_(desc) {
  StreakImages images =
      generateStreakImages(desc.streakLayers, kStreakWidth, kStreakHeight, desc.seed);
  vao_ = gl::VertexArray::create();
  if (desc.draw == scene::RainDraw::Cpu) {
    raster_ = std::make_unique<StreakRaster>(desc, std::move(images));
    return;
  }
  program_ = gl::buildProgram(
      shaders, {{gl::ShaderStage::Vertex, "rain.vert"}, {gl::ShaderStage::Fragment, "rain.frag"}},
      "rain");
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
  indices_ = gl::Buffer::create();
}

void RainRenderer::setDrops(const sph::rain::RainSystem& rain) {
  const std::vector<Vec3>& p = rain.positions();
  const std::vector<std::uint8_t>& layers = rain.layers();
  const std::size_t n = p.size();
  count_ = n;
  velocity_ = rain.velocity();
  if (raster_) {  // copied (12 MB at 1,000,000 drops: in parallel): the system may move on
    positions_.resize(n), layers_.resize(n);
    const auto count = static_cast<std::ptrdiff_t>(n);
    constexpr std::ptrdiff_t kBlock = 1 << 14;
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t b = 0; b < count; b += kBlock) {
      const std::ptrdiff_t e = std::min(count, b + kBlock);
      std::copy(p.begin() + b, p.begin() + e, positions_.begin() + b);
      std::copy(layers.begin() + b, layers.begin() + e, layers_.begin() + b);
    }
    return;
  }
  packed_.resize(4 * n);
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const auto i = static_cast<std::size_t>(k);
    packed_[4 * i] = p[i].x(), packed_[4 * i + 1] = p[i].y(), packed_[4 * i + 2] = p[i].z();
    packed_[4 * i + 3] = layers[i];
  }
  const auto bytes = static_cast<GLsizeiptr>(packed_.size() * sizeof(float));
  if (n > dropCapacity_) {  // reallocated only when the budget grows
    glNamedBufferData(drops_.id(), bytes, packed_.data(), GL_STREAM_DRAW);
    dropCapacity_ = n;
  } else if (n > 0) {
    glNamedBufferSubData(drops_.id(), 0, bytes, packed_.data());
  }
  if (n > indexCapacity_) {  // the index pattern depends on the count only
    std::vector<GLuint> index(6 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto c = static_cast<GLuint>(4 * i);
      const GLuint quad[6] = {c, c + 1, c + 2, c + 2, c + 1, c + 3};
      std::copy(quad, quad + 6, index.begin() + static_cast<std::ptrdiff_t>(6 * i));
    }
    glNamedBufferData(indices_.id(), static_cast<GLsizeiptr>(index.size() * sizeof(GLuint)),
                      index.data(), GL_STATIC_DRAW);
    indexCapacity_ = n;
  }
}

void RainRenderer::draw(const scene::CameraFrame& camera, const frame::Lighting& lighting) {
  if (count_ == 0) return;
  if (raster_) {
    drawCpu(camera, lighting);
  } else {
    drawTriangles(camera, lighting);
  }
}

void RainRenderer::drawCpu(const scene::CameraFrame& camera, const frame::Lighting& lighting) {
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  const int w = viewport[2], h = viewport[3];
  if (w <= 0 || h <= 0) return;
  // The frame's depth (the water and solids the streaks pass behind) and colour, once: the
  // streaks are composed over the colour here and the result copied back (a blit of the same
  // format, which llvmpipe does as a copy). Blending a float layer over the frame in a
  // full-screen pass cost 3-10 ms on llvmpipe, nearly all in fetching its texels
  // (docs/notes/2026-11-27-rain-respawn-and-sums.md, "The sums' runs in strips and the composite
  // on the CPU").
  GLint drawFramebuffer = 0, drawBuffer = GL_NONE;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFramebuffer);
  glGetIntegerv(GL_DRAW_BUFFER0, &drawBuffer);  // the colour the streaks are drawn into
  const GLuint target = static_cast<GLuint>(drawFramebuffer);
  const gl::PixelRect rect{viewport[0], viewport[1], w, h};
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  depth_.resize(pixels);
  colour_.resize(4 * pixels);
  gl::readPixels(target, GL_NONE, rect, GL_DEPTH_COMPONENT, GL_FLOAT, depth_.data());
  gl::readPixels(target, static_cast<GLenum>(drawBuffer), rect, GL_RGBA, GL_UNSIGNED_BYTE,
                 colour_.data());

  raster_->draw(StreakView{camera, w, h}, StreakDrops{&positions_, &layers_, velocity_},
                kUnlitTint * lighting.background, depth_.data());
  composeOver(raster_->layer(), colour_);

  // Into every draw buffer of the frame: the frame draws into its colour only while its layers
  // draw (render/splat/SplatRenderer.cpp, drawLayers). Nothing draws the rain with a scissor test,
  // which would clip the blit.
  composed_.upload(w, h, GL_RGBA, colour_.data());
  composed_.blit(target, viewport[0], viewport[1]);
}

void RainRenderer::drawTriangles(const scene::CameraFrame& camera,
                                 const frame::Lighting& lighting) {
  const GLuint p = program_.id();
  glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "u_projView"), 1, GL_FALSE,
                            camera.projView.m.data());
  frame::setVec3(p, "u_eye", camera.eye);
  frame::setVec3(p, "u_right", camera.right);
  frame::setVec3(p, "u_velocity", velocity_);
  frame::setFloat(p, "u_exposure", desc_.exposure);
  frame::setFloat(p, "u_width", desc_.dropWidth);
  frame::setVec3(p, "u_unlit", kUnlitTint * lighting.background);
  frame::setSpotlightUniforms(p, desc_.spotlight);
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
  glVertexArrayElementBuffer(vao_.id(), indices_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, drops_.id());
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * count_), GL_UNSIGNED_INT, nullptr);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

}  // namespace sph::render::rain
