#include "render/cdt/CdtGl.h"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "render/gl/GlError.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/Shader.h"
#include "sim/cdt/CdtConstants.h"

namespace sph::render::cdt {
namespace {

constexpr GLuint kNoKey = 0xFFFFFFFFu;

void checkGl(const char* where) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", e);
    throw std::runtime_error(std::string("cdt-gl: OpenGL error ") + code + " in " + where);
  }
}

// Vertex layout of CdtParticleGpu on one vertex array (the transform feedback writes the same).
void describeVertices(GLuint vao, GLuint buffer) {
  glVertexArrayVertexBuffer(vao, 0, buffer, 0, sizeof(CdtParticleGpu));
  auto attribute = [&](int location, int components, GLuint offset) {
    glEnableVertexArrayAttrib(vao, static_cast<GLuint>(location));
    glVertexArrayAttribFormat(vao, static_cast<GLuint>(location), components, GL_FLOAT, GL_FALSE,
                              offset);
    glVertexArrayAttribBinding(vao, static_cast<GLuint>(location), 0);
  };
  attribute(sph::cdt::kAttribPositionTime, 4, offsetof(CdtParticleGpu, position));
  attribute(sph::cdt::kAttribVelocity, 3, offsetof(CdtParticleGpu, velocity));
  attribute(sph::cdt::kAttribAcceleration, 3, offsetof(CdtParticleGpu, acceleration));
  glEnableVertexArrayAttrib(vao, sph::cdt::kAttribId);
  glVertexArrayAttribIFormat(vao, sph::cdt::kAttribId, 1, GL_UNSIGNED_INT,
                             offsetof(CdtParticleGpu, id));
  glVertexArrayAttribBinding(vao, sph::cdt::kAttribId, 0);
}

gl::Texture texture2d(GLenum format, int w, int h) {
  gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
  glTextureStorage2D(t.id(), 1, format, w, h);
  // Exact integer addressing only (texelFetch / imageLoad); nearest in case anything samples.
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}

}  // namespace

CdtGl::CdtGl(const sph::cdt::Settings& settings, const gl::ShaderLibrary& shaders)
    : settings_(settings) {
  if (settings.layers < 1 || settings.layers > sph::cdt::kMaxLayers)
    throw std::invalid_argument("cdt-gl: layers out of range");
  collide_ = gl::buildProgram(shaders,
                              {{gl::ShaderStage::Vertex, "cdt_collide.vert"},
                               {gl::ShaderStage::Fragment, "cdt_write.frag"}},
                              "cdt-collide");
  if (settings.rasterWrite) {
    peel_ = gl::buildProgram(
        shaders,
        {{gl::ShaderStage::Vertex, "cdt_peel.vert"}, {gl::ShaderStage::Fragment, "cdt_write.frag"}},
        "cdt-peel");
    glProgramUniform1i(collide_.id(), glGetUniformLocation(collide_.id(), "u_Peel"), 0);
    glProgramUniform1i(peel_.id(), glGetUniformLocation(peel_.id(), "u_Peel"), 1);
  } else {
    write_ = gl::buildProgram(shaders, {{gl::ShaderStage::Compute, "cdt_write.comp"}}, "cdt-write");
  }

  params_ = gl::Buffer::create();
  glNamedBufferStorage(params_.id(), sizeof(CdtParamsGpu), nullptr, GL_DYNAMIC_STORAGE_BIT);
  feedback_ = gl::TransformFeedback::create();
  for (int s = 0; s < 2; ++s) vertexArray_[s] = gl::VertexArray::create();

  const int w = settings.view.width, h = settings.view.height;
  depth_ = gl::Renderbuffer::create();
  glNamedRenderbufferStorage(depth_.id(), GL_DEPTH_COMPONENT32F, w, h);
  const GLenum drawBuffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  for (int s = 0; s < 2; ++s) {
    colour_[s] = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(colour_[s].id(), 1, GL_RGBA32F, w, h, settings.layers);
    glTextureParameteri(colour_[s].id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(colour_[s].id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    for (int l = 0; l < settings.layers; ++l) {
      depthKey_[s][l] = texture2d(GL_R32UI, w, h);
      indexKey_[s][l] = texture2d(GL_R32UI, w, h);
      framebuffer_[s][l] = gl::Framebuffer::create();
      const GLuint fb = framebuffer_[s][l].id();
      glNamedFramebufferTextureLayer(fb, GL_COLOR_ATTACHMENT0, colour_[s].id(), 0, l);
      glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT1, depthKey_[s][l].id(), 0);
      glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT2, indexKey_[s][l].id(), 0);
      glNamedFramebufferRenderbuffer(fb, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.id());
      glNamedFramebufferDrawBuffers(fb, 3, drawBuffers);
      const GLenum status = glCheckNamedFramebufferStatus(fb, GL_FRAMEBUFFER);
      if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw gl::GlUnavailable(
            "cdt-gl: the driver cannot render into an RGBA32F + R32UI collision detection texture "
            "(framebuffer status " +
            std::to_string(status) + ")");
      }
    }
  }
  reset();
  checkGl("setup");
}

CdtGl::~CdtGl() = default;

// Every texel empty: no position (w = kEmptyTexel) and the largest key.
void CdtGl::reset() {
  for (int s = 0; s < 2; ++s) {
    const GLfloat empty[4] = {0, 0, 0, sph::cdt::kEmptyTexel};
    glClearTexImage(colour_[s].id(), 0, GL_RGBA, GL_FLOAT, empty);
    for (int l = 0; l < settings_.layers; ++l) {
      glClearTexImage(depthKey_[s][l].id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNoKey);
      glClearTexImage(indexKey_[s][l].id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNoKey);
    }
  }
  valid_ = false;
}

void CdtGl::allocate(std::size_t capacity) {
  if (capacity <= capacity_) return;
  capacity = std::max(capacity, capacity_ + capacity_ / 2);
  for (int s = 0; s < 2; ++s) {
    // Reallocating loses the other buffer's content; upload() refills the one that is read.
    state_[s] = gl::Buffer::create();
    glNamedBufferStorage(state_[s].id(), static_cast<GLsizeiptr>(capacity * sizeof(CdtParticleGpu)),
                         nullptr, GL_DYNAMIC_STORAGE_BIT);
    describeVertices(vertexArray_[s].id(), state_[s].id());
  }
  diagnostics_ = gl::Buffer::create();
  glNamedBufferStorage(diagnostics_.id(),
                       static_cast<GLsizeiptr>(capacity * sizeof(sph::cdt::Diagnostics)), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  writeKeys_ = gl::Buffer::create();
  glNamedBufferStorage(writeKeys_.id(),
                       static_cast<GLsizeiptr>(capacity * 2 * sizeof(std::uint32_t)), nullptr, 0);
  capacity_ = capacity;
}

void CdtGl::upload(const Particles& p) {
  const std::size_t n = p.size();
  allocate(n);
  staging_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    // A precondition: runs never start with a scene that could pass it (requireIdsInRange).
    if (p.id[i] >= sph::cdt::kMaxId)
      throw std::invalid_argument(
          "cdt-gl: particle ids must stay below 2^24 (the texture stores them as floats)");
    CdtParticleGpu& g = staging_[i];
    g.position[0] = p.x[i], g.position[1] = p.y[i], g.position[2] = p.z[i];
    g.collideTime = p.collideTime[i];
    g.velocity[0] = p.vx[i], g.velocity[1] = p.vy[i], g.velocity[2] = p.vz[i];
    g.id = p.id[i];
    g.acceleration[0] = p.ax[i], g.acceleration[1] = p.ay[i], g.acceleration[2] = p.az[i];
    g.unused = 0;
  }
  if (n > 0) {
    glNamedBufferSubData(state_[current_].id(), 0,
                         static_cast<GLsizeiptr>(n * sizeof(CdtParticleGpu)), staging_.data());
  }
  count_ = n;
}

void CdtGl::writeAtomic(int side) {
  const GLuint program = write_.id();
  glUseProgram(program);
  glProgramUniform1ui(program, glGetUniformLocation(program, "u_Count"),
                      static_cast<GLuint>(count_));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, sph::cdt::kParticleBinding, state_[side].id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, sph::cdt::kWriteKeyBinding, writeKeys_.id());
  const GLint stage = glGetUniformLocation(program, "u_Stage"),
              peel = glGetUniformLocation(program, "u_Peel"),
              first = glGetUniformLocation(program, "u_First");
  // GL guarantees 65,535 work groups per dispatch dimension (Mesa allows no more): past 4,194,240
  // particles one dispatch failed and wrote nothing, so the particles go in several.
  constexpr std::size_t kPerDispatch = std::size_t{65535} * sph::cdt::kWriteGroupSize;
  for (int l = 0; l < settings_.layers; ++l) {
    glBindImageTexture(sph::cdt::kImageColour, colour_[side].id(), 0, GL_FALSE, l, GL_WRITE_ONLY,
                       GL_RGBA32F);
    glBindImageTexture(sph::cdt::kImageDepthKey, depthKey_[side][l].id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(sph::cdt::kImageIndexKey, indexKey_[side][l].id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R32UI);
    const int previous = l > 0 ? l - 1 : 0;  // bound but unused on the first layer
    glBindImageTexture(sph::cdt::kImagePreviousDepth, depthKey_[side][previous].id(), 0, GL_FALSE,
                       0, GL_READ_ONLY, GL_R32UI);
    glBindImageTexture(sph::cdt::kImagePreviousIndex, indexKey_[side][previous].id(), 0, GL_FALSE,
                       0, GL_READ_ONLY, GL_R32UI);
    glProgramUniform1i(program, peel, l > 0 ? 1 : 0);
    for (int s = 0; s < 3; ++s) {
      glProgramUniform1i(program, stage, s);
      for (std::size_t begin = 0; begin < count_; begin += kPerDispatch) {
        const std::size_t n = std::min(kPerDispatch, count_ - begin);
        glProgramUniform1ui(program, first, static_cast<GLuint>(begin));
        glDispatchCompute(
            static_cast<GLuint>((n + sph::cdt::kWriteGroupSize - 1) / sph::cdt::kWriteGroupSize), 1,
            1);
      }
      glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void CdtGl::step(float dt, bool integrate) {
  const sph::cdt::Settings& s = settings_;
  CdtParamsGpu params{};
  std::memcpy(params.projView, s.view.projView.m.data(), sizeof params.projView);
  params.texture[0] = s.view.width, params.texture[1] = s.view.height;
  params.texture[2] = s.layers, params.texture[3] = s.texelRange;
  params.control[0] = s.maxTexelRange;
  std::uint32_t flags = s.flags;
  if (integrate) flags |= sph::cdt::kFlagIntegrate;
  if (valid_) flags |= sph::cdt::kFlagTextureValid;
  params.control[1] = static_cast<std::int32_t>(flags);
  params.scalars[0] = s.range, params.scalars[1] = dt, params.scalars[2] = s.speedFactor,
  params.scalars[3] = s.cooldown;
  params.scalars2[0] = s.view.texelScale;
  glNamedBufferSubData(params_.id(), 0, sizeof params, &params);
  glBindBufferBase(GL_UNIFORM_BUFFER, sph::cdt::kParamsBinding, params_.id());

  const int read = current_, write = 1 - current_;
  // The next texture starts empty.
  const GLfloat empty[4] = {0, 0, 0, sph::cdt::kEmptyTexel};
  glClearTexImage(colour_[write].id(), 0, GL_RGBA, GL_FLOAT, empty);
  for (int l = 0; l < s.layers; ++l) {
    glClearTexImage(depthKey_[write][l].id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNoKey);
    glClearTexImage(indexKey_[write][l].id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNoKey);
  }

  if (count_ > 0) {
    // The collision pass (seed 000, Fig. 3): one vertex per particle reads the previous texture
    // and feeds its new state back into the other buffer. With the raster write the same draw
    // also rasterises layer 0 of the next texture, as in the paper.
    glUseProgram(collide_.id());
    glBindTextureUnit(sph::cdt::kLayerUnit, colour_[read].id());
    glBindTextureUnit(sph::cdt::kPeelDepthUnit, 0);
    glBindTextureUnit(sph::cdt::kPeelIndexUnit, 0);
    const GLfloat farDepth = 1.0f;
    if (s.rasterWrite) {
      glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_[write][0].id());
      glClearNamedFramebufferfv(framebuffer_[write][0].id(), GL_DEPTH, 0, &farDepth);
      glViewport(0, 0, s.view.width, s.view.height);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      glDepthMask(GL_TRUE);
      glDisable(GL_BLEND);
      glDisable(GL_PROGRAM_POINT_SIZE);
      glPointSize(1.0f);
    } else {
      // Nothing is rasterised, but a draw needs a complete framebuffer and a surfaceless
      // context has no default one.
      glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_[write][0].id());
      glEnable(GL_RASTERIZER_DISCARD);
    }
    glBindVertexArray(vertexArray_[read].id());
    glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, feedback_.id());
    glTransformFeedbackBufferBase(feedback_.id(), sph::cdt::kXfbState, state_[write].id());
    glTransformFeedbackBufferBase(feedback_.id(), sph::cdt::kXfbDiagnostics, diagnostics_.id());
    glTransformFeedbackBufferBase(feedback_.id(), sph::cdt::kXfbWriteKeys, writeKeys_.id());
    glBeginTransformFeedback(GL_POINTS);
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(count_));
    glEndTransformFeedback();
    glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, 0);
    glBindTextureUnit(sph::cdt::kLayerUnit, 0);
    if (s.rasterWrite) {
      // Further layers: draw the new positions again, keeping what comes after the previous layer.
      if (s.layers > 1) {
        glUseProgram(peel_.id());
        glBindVertexArray(vertexArray_[write].id());
        for (int l = 1; l < s.layers; ++l) {
          glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_[write][l].id());
          glClearNamedFramebufferfv(framebuffer_[write][l].id(), GL_DEPTH, 0, &farDepth);
          glBindTextureUnit(sph::cdt::kPeelDepthUnit, depthKey_[write][l - 1].id());
          glBindTextureUnit(sph::cdt::kPeelIndexUnit, indexKey_[write][l - 1].id());
          glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(count_));
        }
        glBindTextureUnit(sph::cdt::kPeelDepthUnit, 0);
        glBindTextureUnit(sph::cdt::kPeelIndexUnit, 0);
      }
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
    } else {
      glDisable(GL_RASTERIZER_DISCARD);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      writeAtomic(write);
    }
    glBindVertexArray(0);
  }
  checkGl("step");
  current_ = write;
  valid_ = true;
}

void CdtGl::download(Particles& p) const {
  if (p.size() != count_)
    throw std::invalid_argument("cdt-gl: download into particles of another size");
  if (count_ == 0) return;
  staging_.resize(count_);
  glGetNamedBufferSubData(state_[current_].id(), 0,
                          static_cast<GLsizeiptr>(count_ * sizeof(CdtParticleGpu)),
                          staging_.data());
  for (std::size_t i = 0; i < count_; ++i) {
    const CdtParticleGpu& g = staging_[i];
    p.x[i] = g.position[0], p.y[i] = g.position[1], p.z[i] = g.position[2];
    p.collideTime[i] = g.collideTime;
    p.vx[i] = g.velocity[0], p.vy[i] = g.velocity[1], p.vz[i] = g.velocity[2];
  }
}

std::vector<sph::cdt::Diagnostics> CdtGl::diagnostics() const {
  std::vector<sph::cdt::Diagnostics> d(count_);
  if (count_ > 0) {
    glGetNamedBufferSubData(diagnostics_.id(), 0,
                            static_cast<GLsizeiptr>(count_ * sizeof(sph::cdt::Diagnostics)),
                            d.data());
  }
  return d;
}

sph::cdt::Texture CdtGl::readTexture() const {
  sph::cdt::Texture t;
  t.width = settings_.view.width, t.height = settings_.view.height, t.layers = settings_.layers;
  const std::size_t plane = static_cast<std::size_t>(t.width) * t.height;
  t.texels.resize(plane * t.layers);
  t.keys.resize(plane * t.layers);
  std::vector<std::uint32_t> depth(plane), index(plane);
  for (int l = 0; l < t.layers; ++l) {
    gl::readTextureLayer(colour_[current_].id(), l, t.width, t.height, GL_RGBA, GL_FLOAT,
                         plane * 16, t.texels.data() + l * plane);
    gl::readTexture(depthKey_[current_][l].id(), GL_RED_INTEGER, GL_UNSIGNED_INT, plane * 4,
                    depth.data());
    gl::readTexture(indexKey_[current_][l].id(), GL_RED_INTEGER, GL_UNSIGNED_INT, plane * 4,
                    index.data());
    for (std::size_t i = 0; i < plane; ++i)
      t.keys[l * plane + i] = (static_cast<std::uint64_t>(depth[i]) << 32) | index[i];
  }
  checkGl("readTexture");
  return t;
}

}  // namespace sph::render::cdt
