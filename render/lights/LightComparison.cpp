#include "render/lights/LightComparison.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "render/frame/Lighting.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/Shader.h"
#include "sim/scene/Camera.h"

namespace sph::render::lights {
namespace {

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

frame::RenderImage picture(const SolidGBuffer& g, const std::vector<Vec3>& colour) {
  frame::RenderImage image;
  image.resize(g.width, g.height, false);
  for (std::size_t k = 0; k < g.pixels.size(); ++k)
    for (int a = 0; a < 3; ++a)
      image.rgb[3 * g.pixels[k] + static_cast<std::size_t>(a)] = frame::toSrgb8(colour[k][a]);
  return image;
}

}  // namespace

std::string FilterSetting::label() const {
  std::string s = nameOf(filter);
  if (filter == scene::LightFilter::Tricubic) s += " t" + std::to_string(tension).substr(0, 3);
  if (oversampling > 1) s += " x" + std::to_string(oversampling * oversampling * oversampling);
  return s;
}

SolidGBuffer solidGBuffer(solids::SolidRenderer& solids, const scene::CameraDesc& camera, int width,
                          int height, const gl::ShaderLibrary& shaders) {
  const gl::Program program = gl::buildProgram(
      shaders,
      {{gl::ShaderStage::Vertex, "solid.vert"}, {gl::ShaderStage::Fragment, "solid_gbuffer.frag"}},
      "solid G-buffer");
  gl::Texture position = gl::Texture::create(GL_TEXTURE_2D);
  gl::Texture normal = gl::Texture::create(GL_TEXTURE_2D);
  gl::Renderbuffer depth = gl::Renderbuffer::create();
  glTextureStorage2D(position.id(), 1, GL_RGBA32F, width, height);
  glTextureStorage2D(normal.id(), 1, GL_RGBA32F, width, height);
  glNamedRenderbufferStorage(depth.id(), GL_DEPTH_COMPONENT24, width, height);
  gl::Framebuffer fbo = gl::Framebuffer::create();
  glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, position.id(), 0);
  glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT1, normal.id(), 0);
  glNamedFramebufferRenderbuffer(fbo.id(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth.id());
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fbo.id(), 2, buffers);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  glViewport(0, 0, width, height);
  const float zero[4] = {0, 0, 0, 0};
  const float one = 1.0f;
  glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, zero);
  glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 1, zero);
  glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &one);
  const scene::CameraFrame cf = cameraFrame(camera, static_cast<float>(width) / height);
  solids.drawWith(program.id(), cf);
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<float> pos(4 * n), nrm(4 * n);
  gl::readTexture(position.id(), GL_RGBA, GL_FLOAT, pos.size() * 4, pos.data());
  gl::readTexture(normal.id(), GL_RGBA, GL_FLOAT, nrm.size() * 4, nrm.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  SolidGBuffer g;
  g.width = width, g.height = height;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t src = static_cast<std::size_t>(y) * width + x;  // GL: row 0 at the bottom
      if (pos[4 * src + 3] == 0) continue;
      ProbePoint p;
      p.position = Vec3(pos[4 * src], pos[4 * src + 1], pos[4 * src + 2]);
      p.normal = Vec3(nrm[4 * src], nrm[4 * src + 1], nrm[4 * src + 2]).normalized();
      p.toEye = (cf.eye - p.position).normalized();
      g.points.push_back(p);
      g.pixels.push_back(static_cast<std::size_t>(height - 1 - y) * width + x);
    }
  }
  return g;
}

std::vector<LightComparison> compareLights(LightVolume& volume,
                                           const std::vector<sph::lights::LightParticle>& lights,
                                           const SolidGBuffer& g, const Vec3& base,
                                           const std::vector<FilterSetting>& settings) {
  std::vector<LightComparison> out;
  const std::size_t n = g.points.size();
  std::vector<Vec3> exactD(n), exactS(n), exactT(n);
  {
    auto start = std::chrono::steady_clock::now();
    const ExactLights exact(volume.desc(), lights);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t k = 0; k < n; ++k) {
      const ProbePoint& p = g.points[k];
      const LightTerms t = exact.at(p.position, p.normal, p.toEye, base);
      exactD[k] = t.diffuse, exactS[k] = t.specular, exactT[k] = t.diffuse + t.specular;
    }
    LightComparison e;
    e.name = "exact";
    e.image = picture(g, exactT);
    e.seconds = since(start);
    e.total.psnr = e.diffuse.psnr = e.specular.psnr = std::numeric_limits<double>::infinity();
    out.push_back(std::move(e));
  }
  const int terms = volume.terms;
  // The first dispatch of the probe compiles llvmpipe's shader variant: not part of any timing.
  volume.probe(
      std::vector<ProbePoint>(g.points.begin(), g.points.begin() + std::min<std::size_t>(n, 64)),
      base);
  const scene::LightsDesc saved = volume.desc();
  for (const FilterSetting& s : settings) {
    volume.setFilter(s.filter, s.tension, s.oversampling);
    LightComparison c;
    c.name = s.label();
    auto start = std::chrono::steady_clock::now();
    volume.terms = 3;
    const std::vector<Vec3> total = volume.shade(g.points, base);
    c.seconds = since(start);
    volume.terms = 1;
    const std::vector<Vec3> diffuse = volume.shade(g.points, base);
    volume.terms = 2;
    const std::vector<Vec3> specular = volume.shade(g.points, base);
    c.total = lightError(total, exactT);
    c.diffuse = lightError(diffuse, exactD);
    c.specular = lightError(specular, exactS);
    c.image = picture(g, total);
    out.push_back(std::move(c));
  }
  volume.terms = terms;
  volume.setFilter(saved.filter, saved.tension, saved.oversampling);
  return out;
}

}  // namespace sph::render::lights
