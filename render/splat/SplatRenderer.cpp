#include "render/splat/SplatRenderer.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "render/frame/DeferredTarget.h"
#include "render/frame/ExtraLights.h"
#include "render/frame/LightingUniforms.h"
#include "render/frame/ProgramUniforms.h"
#include "render/frame/ReadPicture.h"
#include "render/gl/GlError.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/Shader.h"

namespace sph::render::splat {
namespace {

void setLighting(GLuint p, const frame::Lighting& l) {
  frame::setLightingUniforms(p, l);
  frame::setFloat(p, "u_alpha", l.alpha);
  frame::setInt(p, "u_twoSided", l.alpha < 1.0f ? 1 : 0);
}

// Position (location 0) and normal (location 1) of SplatVertex from binding 0.
void describeVertices(GLuint vao, GLuint buffer, bool instanced) {
  glVertexArrayVertexBuffer(vao, 0, buffer, 0, sizeof(SplatVertex));
  for (GLuint a = 0; a < 2; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(
        vao, a, 3, GL_FLOAT, GL_FALSE,
        a == 0 ? offsetof(SplatVertex, position) : offsetof(SplatVertex, normal));
    glVertexArrayAttribBinding(vao, a, 0);
  }
  glVertexArrayBindingDivisor(vao, 0, instanced ? 1 : 0);
}

// Grows-or-refills a buffer with `bytes` of data.
void upload(gl::Buffer& buffer, const void* data, std::size_t bytes) {
  if (bytes == 0) return;
  glNamedBufferData(buffer.id(), static_cast<GLsizeiptr>(bytes), data, GL_STREAM_DRAW);
}

}  // namespace

SplatRenderer::SplatRenderer(int width, int height, const gl::ShaderLibrary& shaders)
    : width_(width), height_(height), shaders_(shaders) {
  pointProgram_ = gl::buildProgram(
      shaders,
      {{gl::ShaderStage::Vertex, "splat_point.vert"}, {gl::ShaderStage::Fragment, "splat.frag"}},
      "point splats", {"SPH_NO_PARTICLE_LIGHTS"});
  quadProgram_ = gl::buildProgram(
      shaders,
      {{gl::ShaderStage::Vertex, "splat_quad.vert"}, {gl::ShaderStage::Fragment, "splat.frag"}},
      "quad splats", {"SPH_NO_PARTICLE_LIGHTS"});
  colour_ = gl::Texture::create(GL_TEXTURE_2D);
  glTextureStorage2D(colour_.id(), 1, GL_RGBA8, width, height);
  normal_ = gl::Texture::create(GL_TEXTURE_2D);
  glTextureStorage2D(normal_.id(), 1, GL_RGBA32F, width, height);
  depth_ = gl::Renderbuffer::create();
  glNamedRenderbufferStorage(depth_.id(), GL_DEPTH_COMPONENT24, width, height);
  framebuffer_ = gl::Framebuffer::create();
  glNamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, colour_.id(), 0);
  glNamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT1, normal_.id(), 0);
  glNamedFramebufferRenderbuffer(framebuffer_.id(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                 depth_.id());
  selectDrawBuffers(frame::ImageContents::ColourAndNormals);
  if (glCheckNamedFramebufferStatus(framebuffer_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw gl::GlError(
        "the splat framebuffer (RGBA8 + RGBA32F + depth) is incomplete on this driver");
  }
  pointBuffer_ = gl::Buffer::create();
  quadBuffer_ = gl::Buffer::create();
  indexBuffer_ = gl::Buffer::create();
  pointVao_ = gl::VertexArray::create();
  quadVao_ = gl::VertexArray::create();
  boundaryBuffer_ = gl::Buffer::create();
  boundaryVao_ = gl::VertexArray::create();
}

void SplatRenderer::setBoundary(std::vector<SplatVertex> points, float halfSide) {
  boundaryCount_ = points.size();
  boundaryHalfSide_ = halfSide;
  upload(boundaryBuffer_, points.data(), points.size() * sizeof(SplatVertex));
  describeVertices(boundaryVao_.id(), boundaryBuffer_.id(), true);
}

void SplatRenderer::drawBoundary(bool offscreen) {
  if (boundaryCount_ == 0) return;
  // Flat grey, lit from the viewer: the points carry their normal towards the camera anyway.
  frame::Lighting wall;
  wall.base = Vec3(0.55f, 0.56f, 0.6f);
  wall.ambient = 1.0f, wall.diffuse = 0.0f, wall.specular = 0.0f, wall.environment = false;
  wall.alpha = 0.09f;
  const GLuint p = pointProgram_.id();
  setLighting(p, wall);
  frame::setFloat(p, "u_halfSide", boundaryHalfSide_);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  if (offscreen) selectDrawBuffers(frame::ImageContents::Colour);
  glUseProgram(p);
  glBindVertexArray(boundaryVao_.id());
  glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(boundaryCount_));
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  if (offscreen) selectDrawBuffers(contents_);
}

void SplatRenderer::drawLayers(frame::FrameLayer::Order order, const scene::CameraFrame& camera,
                               const frame::Lighting& lighting, bool offscreen) {
  // The error figures' frame has the opaque solids (its reference has them too, as a backdrop:
  // drawBackdrop) but nothing drawn after the water (rain): the reference has none.
  const bool scored = offscreen && contents_ == frame::ImageContents::ColourAndNormals;
  if (scored && order == frame::FrameLayer::Order::AfterSplats) return;
  // Layers write colour only: the normal target is the water's.
  if (scored) selectDrawBuffers(frame::ImageContents::Colour);
  for (frame::FrameLayer* layer : layers_) {
    if (layer->order() == order) layer->draw(camera, lighting);
  }
  if (scored) selectDrawBuffers(contents_);
}

bool SplatRenderer::hasLayers(frame::FrameLayer::Order order) const {
  for (const frame::FrameLayer* layer : layers_)
    if (layer->order() == order) return true;
  return false;
}

Backdrop SplatRenderer::drawBackdrop(const scene::CameraDesc& camera,
                                     const frame::Lighting& lighting) {
  contents_ = frame::ImageContents::Colour;
  selectDrawBuffers(contents_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  float bgEncoded[4] = {0, 0, 0, 1};
  for (int k = 0; k < 3; ++k) bgEncoded[k] = frame::toSrgb8(lighting.background[k]) / 255.0f;
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, bgEncoded);
  glClearNamedFramebufferfi(framebuffer_.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glViewport(0, 0, width_, height_);
  drawLayers(frame::FrameLayer::Order::BeforeSplats,
             cameraFrame(camera, static_cast<float>(width_) / height_), lighting, true);
  glFinish();
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  Backdrop b;
  b.width = width_, b.height = height_;
  b.rgb = frame::readPicture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, width_, height_).rgb;
  std::vector<float> depth(n);
  gl::readPixels(framebuffer_.id(), GL_NONE, {0, 0, width_, height_}, GL_DEPTH_COMPONENT, GL_FLOAT,
                 depth.data(), gl::RowOrder::TopFirst);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  b.viewDepth.resize(n);
  // Window depth -> distance along the view axis, inverting gluPerspective's depth mapping.
  const double near = camera.near, far = camera.far;
  for (std::size_t p = 0; p < n; ++p) {
    const double d = depth[p];
    const double ndc = 2 * d - 1;
    b.viewDepth[p] = d >= 1.0
                         ? std::numeric_limits<float>::infinity()
                         : static_cast<float>(2 * near * far / (far + near - ndc * (far - near)));
  }
  return b;
}

void SplatRenderer::selectDrawBuffers(frame::ImageContents contents) {
  const GLenum attachments[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer_.id(), contents == frame::ImageContents::Colour ? 1 : 2,
                                attachments);
}

SplatRenderer::~SplatRenderer() = default;

GLuint SplatRenderer::programFor(SplatKind kind, bool particleLights) {
  if (!particleLights) return kind == SplatKind::Point ? pointProgram_.id() : quadProgram_.id();
  if (litPointProgram_.id() == 0) {
    litPointProgram_ = gl::buildProgram(
        shaders_,
        {{gl::ShaderStage::Vertex, "splat_point.vert"}, {gl::ShaderStage::Fragment, "splat.frag"}},
        "point splats with particle lights");
    litQuadProgram_ = gl::buildProgram(
        shaders_,
        {{gl::ShaderStage::Vertex, "splat_quad.vert"}, {gl::ShaderStage::Fragment, "splat.frag"}},
        "quad splats with particle lights");
  }
  return kind == SplatKind::Point ? litPointProgram_.id() : litQuadProgram_.id();
}

GLuint SplatRenderer::gbufferProgramFor(SplatKind kind) {
  if (gbufferPointProgram_.id() == 0) {
    const std::vector<std::string> defines = {"SPH_NO_PARTICLE_LIGHTS", "SPH_GBUFFER"};
    gbufferPointProgram_ = gl::buildProgram(
        shaders_,
        {{gl::ShaderStage::Vertex, "splat_point.vert"}, {gl::ShaderStage::Fragment, "splat.frag"}},
        "point splats into the G-buffer", defines);
    gbufferQuadProgram_ = gl::buildProgram(
        shaders_,
        {{gl::ShaderStage::Vertex, "splat_quad.vert"}, {gl::ShaderStage::Fragment, "splat.frag"}},
        "quad splats into the G-buffer", defines);
  }
  return kind == SplatKind::Point ? gbufferPointProgram_.id() : gbufferQuadProgram_.id();
}

void SplatRenderer::drawSplats(const SplatFrame& frame, SplatKind kind,
                               const scene::CameraFrame& cam, const frame::Lighting& lighting,
                               GLuint program) {
  setLighting(program, lighting);
  glProgramUniformMatrix4fv(program, glGetUniformLocation(program, "u_projView"), 1, GL_FALSE,
                            cam.projView.m.data());
  frame::setVec3(program, "u_eye", cam.eye);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);  // splats are seen from both sides
  if (lighting.alpha < 1.0f) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  } else {
    glDisable(GL_BLEND);
  }
  glUseProgram(program);
  if (kind == SplatKind::Point) {
    frame::setVec3(program, "u_cameraRight", cam.right);
    frame::setVec3(program, "u_cameraUp", cam.up);
    // Same area as a quad splat of the same size (a square with half-diagonal halfSize).
    frame::setFloat(program, "u_halfSide", frame.halfSize / std::sqrt(2.0f));
    upload(pointBuffer_, frame.points.data(), frame.points.size() * sizeof(SplatVertex));
    describeVertices(pointVao_.id(), pointBuffer_.id(), true);
    glBindVertexArray(pointVao_.id());
    if (!frame.points.empty())
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(frame.points.size()));
  } else {
    upload(quadBuffer_, frame.quads.data(), frame.quads.size() * sizeof(SplatVertex));
    upload(indexBuffer_, frame.indices.data(), frame.indices.size() * sizeof(std::uint32_t));
    describeVertices(quadVao_.id(), quadBuffer_.id(), false);
    glVertexArrayElementBuffer(quadVao_.id(), indexBuffer_.id());
    glBindVertexArray(quadVao_.id());
    if (!frame.indices.empty())
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(frame.indices.size()), GL_UNSIGNED_INT,
                     nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

void SplatRenderer::drawDeferred(const SplatFrame& frame, SplatKind kind,
                                 const scene::CameraFrame& cam, const frame::Lighting& lighting,
                                 int w, int h, bool offscreen) {
  using Clock = std::chrono::steady_clock;
  GLint target = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
  if (!deferred_) deferred_ = std::make_unique<frame::DeferredTarget>(shaders_);
  const auto start = Clock::now();
  // 1. The G-buffer: the opaque layers (solids) and the water when it is opaque.
  const bool opaque = lighting.alpha >= 1.0f;
  const bool points = opaque && kind == SplatKind::Point && !frame.points.empty();
  deferred_->begin(w, h, lighting.extra->shadesOnCpu(), points);
  glViewport(0, 0, w, h);
  // The error figures' frame has the solids too (drawLayers); the lighting pass keeps them out of
  // its normal target.
  std::vector<frame::FrameLayer*> forward;
  for (frame::FrameLayer* layer : layers_) {
    if (layer->order() == frame::FrameLayer::Order::BeforeSplats &&
        !layer->drawGBuffer(cam, lighting))
      forward.push_back(layer);
  }
  if (opaque) drawSplats(frame, kind, cam, lighting, gbufferProgramFor(kind));
  glFinish();  // the passes' times apart (Fig. 11's breakdown; llvmpipe drains between them anyway)
  const auto gbuffer = Clock::now();
  // 2. One full-screen pass adds the particle lights where the G-buffer holds a surface. With
  // lights.shade "cpu" each pixel's colour is computed on the CPU first (passes_.particles) and
  // copied: by that pass, or by a blit where nothing drawn after needs the depth.
  frame::DeferredTarget::Output out;
  out.framebuffer = static_cast<GLuint>(target);
  out.normals = offscreen && contents_ == frame::ImageContents::ColourAndNormals;
  // The frame's depth is wanted only by what is drawn after this pass (each depth tested):
  // forward layers, translucent water, the walls' points, the layers after the water.
  const bool water = kind == SplatKind::Point ? !frame.points.empty() : !frame.indices.empty();
  out.depth = !forward.empty() || (!opaque && water) || boundaryCount_ > 0 ||
              hasLayers(frame::FrameLayer::Order::AfterSplats);
  for (int k = 0; k < 3; ++k)
    out.background[static_cast<std::size_t>(k)] = frame::toSrgb8(lighting.background[k]);
  passes_.particles = deferred_->light(out, *lighting.extra, cam.eye, cam.projView);
  glFinish();
  passes_.gbuffer = std::chrono::duration<double>(gbuffer - start).count();
  passes_.lighting =
      std::chrono::duration<double>(Clock::now() - gbuffer).count() - passes_.particles;
  // 3. Forward on top, depth tested against the lit frame: layers without a G-buffer program and
  // translucent water, which a G-buffer of one surface per pixel cannot blend (docs/lights.md).
  if (out.normals) selectDrawBuffers(frame::ImageContents::Colour);
  for (frame::FrameLayer* layer : forward) layer->draw(cam, lighting);
  if (out.normals) selectDrawBuffers(contents_);
  if (!opaque) drawSplats(frame, kind, cam, lighting, programFor(kind, true));
}

double SplatRenderer::draw(const SplatFrame& frame, SplatKind kind, const scene::CameraDesc& camera,
                           const frame::Lighting& lighting, int w, int h, bool offscreen) {
  const auto start = std::chrono::steady_clock::now();
  const scene::CameraFrame cam = cameraFrame(camera, static_cast<float>(w) / h);
  glViewport(0, 0, w, h);
  passes_ = DrawPasses{};
  if (lighting.extra != nullptr && lighting.extra->deferred()) {
    drawDeferred(frame, kind, cam, lighting, w, h, offscreen);
  } else {
    drawLayers(frame::FrameLayer::Order::BeforeSplats, cam, lighting, offscreen);
    drawSplats(frame, kind, cam, lighting, programFor(kind, lighting.extra != nullptr));
  }
  if (boundaryCount_) {
    // The point program also draws the walls: give it this frame's camera first.
    const GLuint p = pointProgram_.id();
    glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "u_projView"), 1, GL_FALSE,
                              cam.projView.m.data());
    frame::setVec3(p, "u_eye", cam.eye);
    frame::setVec3(p, "u_cameraRight", cam.right);
    frame::setVec3(p, "u_cameraUp", cam.up);
    drawBoundary(offscreen);
  }
  drawLayers(frame::FrameLayer::Order::AfterSplats, cam, lighting, offscreen);
  glFinish();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

frame::RenderImage SplatRenderer::render(const SplatFrame& frame, SplatKind kind,
                                         const scene::CameraDesc& camera,
                                         const frame::Lighting& lighting,
                                         frame::ImageContents contents) {
  const bool withNormals = contents == frame::ImageContents::ColourAndNormals;
  contents_ = contents;
  selectDrawBuffers(contents);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  // The background in the same sRGB encoding the shaders write.
  float bgEncoded[4] = {0, 0, 0, 1};
  for (int k = 0; k < 3; ++k) bgEncoded[k] = frame::toSrgb8(lighting.background[k]) / 255.0f;
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, bgEncoded);
  if (withNormals) glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 1, zero);
  glClearNamedFramebufferfi(framebuffer_.id(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
  const double seconds = draw(frame, kind, camera, lighting, width_, height_, true);
  frame::RenderImage image =
      frame::readPicture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, width_, height_);
  image.seconds = seconds;
  if (withNormals) {
    const std::size_t n = static_cast<std::size_t>(width_) * height_;
    std::vector<float> normal(4 * n);
    gl::readPixels(framebuffer_.id(), GL_COLOR_ATTACHMENT1, {0, 0, width_, height_}, GL_RGBA,
                   GL_FLOAT, normal.data(), gl::RowOrder::TopFirst);
    image.normal.resize(3 * n);
    image.covered.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      for (std::size_t k = 0; k < 3; ++k) image.normal[3 * p + k] = normal[4 * p + k];
      image.covered[p] = normal[4 * p + 3] > 0.5f ? 1 : 0;
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return image;
}

void SplatRenderer::drawToScreen(const SplatFrame& frame, SplatKind kind,
                                 const scene::CameraDesc& camera, const frame::Lighting& lighting,
                                 int viewportWidth, int viewportHeight) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  // Encoded like everything the shaders write (the window's framebuffer is not sRGB).
  glClearColor(frame::toSrgb8(lighting.background.x()) / 255.0f,
               frame::toSrgb8(lighting.background.y()) / 255.0f,
               frame::toSrgb8(lighting.background.z()) / 255.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  draw(frame, kind, camera, lighting, viewportWidth, viewportHeight, false);
}

}  // namespace sph::render::splat
