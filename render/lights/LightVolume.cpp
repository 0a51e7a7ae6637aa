#include "render/lights/LightVolume.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>

#include "render/gl/GlError.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/Shader.h"
#include "render/lights/CpuAccumulation.h"
#include "render/lights/CpuShading.h"
#include "sim/InputError.h"
#include "sim/Parallel.h"

namespace sph::render::lights {
namespace {

constexpr GLuint kColourUnit = 6, kDirectionUnit = 7;  // extra_lights.glsl's bindings

void setVolumeUniforms(GLuint p, const scene::LightsDesc& d) {
  glProgramUniform3f(p, glGetUniformLocation(p, "u_origin"), d.origin.x(), d.origin.y(),
                     d.origin.z());
  glProgramUniform1f(p, glGetUniformLocation(p, "u_voxelSize"), d.voxelSize);
  glProgramUniform3i(p, glGetUniformLocation(p, "u_voxels"), d.voxels[0], d.voxels[1], d.voxels[2]);
}

std::string sizeText(const scene::LightsDesc& d) {
  return std::to_string(d.voxels[0]) + " x " + std::to_string(d.voxels[1]) + " x " +
         std::to_string(d.voxels[2]) + " voxels (" +
         std::to_string(static_cast<long long>(d.memoryBytes() / 1048576.0)) + " MiB)";
}

}  // namespace

float fixedScale(const scene::LightsDesc& d) {
  return kFixedSteps / d.intensity;
}

float safeFixedScale(const scene::LightsDesc& d,
                     const std::vector<sph::lights::LightParticle>& lights) {
  // One light adds at most round(x * scale) <= x * scale + 1/2 steps to a sum, x its brightest
  // value; n of them fit while n (x scale + 1/2) <= 2^31 - 1.
  double brightest = 0;
  for (const sph::lights::LightParticle& l : lights) {
    const float colour = std::max({l.colour[0], l.colour[1], l.colour[2]}) / d.attenuation[0];
    brightest =
        std::max({brightest, static_cast<double>(colour), static_cast<double>(l.colour[3])});
  }
  if (lights.empty() || brightest <= 0) return fixedScale(d);
  const double n = static_cast<double>(lights.size());
  const double scale = (2147483647.0 / n - 0.5) / brightest;
  return static_cast<float>(std::min(scale * (1 - 1e-6), static_cast<double>(fixedScale(d))));
}

namespace {

gl::Texture volumeTexture(const scene::LightsDesc& d, GLenum format) {
  gl::Texture t = gl::Texture::create(GL_TEXTURE_3D);
  glTextureStorage3D(t.id(), 1, format, d.voxels[0], d.voxels[1], d.voxels[2]);
  return t;
}

// Zero in the voxels of `b` of texture `t`.
void clearBox(const gl::Texture& t, const VoxelBox& b, bool integer) {
  if (b.empty()) return;
  const float zero[4] = {0, 0, 0, 0};
  const GLint izero = 0;
  glClearTexSubImage(t.id(), 0, b.lo[0], b.lo[1], b.lo[2], b.hi[0] - b.lo[0], b.hi[1] - b.lo[1],
                     b.hi[2] - b.lo[2], integer ? GL_RED_INTEGER : GL_RGBA,
                     integer ? GL_INT : GL_FLOAT,
                     integer ? static_cast<const void*>(&izero) : zero);
}

bool sameBox(const VoxelBox& a, const VoxelBox& b) {
  return a.lo == b.lo && a.hi == b.hi;
}

// Whether box `outer` holds every voxel of `inner`.
bool holds(const VoxelBox& outer, const VoxelBox& inner) {
  if (inner.empty()) return true;
  for (std::size_t a = 0; a < 3; ++a)
    if (inner.lo[a] < outer.lo[a] || inner.hi[a] > outer.hi[a]) return false;
  return true;
}

// `auto` decided for this GL: llvmpipe and the other software rasterisers run the compute
// shader's atomics a lane at a time on the CPU, where OpenMP over z slices is 7-10x faster
// (docs/benchmarks.md, "Particle lights"); a GPU keeps the atomic path.
scene::LightsDesc decided(scene::LightsDesc desc) {
  if (desc.accumulate != scene::LightAccumulate::Auto) return desc;
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string renderer = name ? name : "";
  const bool software = renderer.find("llvmpipe") != std::string::npos ||
                        renderer.find("softpipe") != std::string::npos ||
                        renderer.find("SwiftShader") != std::string::npos;
  desc.accumulate = software ? scene::LightAccumulate::Cpu : scene::LightAccumulate::Atomic;
  return desc;
}

// lights.shade decided: "auto" is "cpu" where the volume is on the CPU and the frame deferred
// (the lighting pass's two 3D-texture fetches a pixel are llvmpipe's slowest part of Fig. 11,
// docs/benchmarks.md) with a filter the CPU pass has; "cpu" asked for where it cannot work is
// refused as the scene loader refuses it (io/scene/ViewSections.cpp).
scene::LightsDesc decidedShade(scene::LightsDesc desc) {
  const bool onCpu = desc.accumulate == scene::LightAccumulate::Cpu;
  const bool deferred = desc.pipeline == scene::LightPipeline::Deferred;
  const bool filter = desc.filter != scene::LightFilter::Tricubic;
  if (desc.shade == scene::LightShade::Auto)
    desc.shade = onCpu && deferred && filter ? scene::LightShade::Cpu : scene::LightShade::Gl;
  if (desc.shade == scene::LightShade::Cpu && !(onCpu && deferred && filter))
    throw InputError(
        "lights.shade: \"cpu\" needs \"accumulate\": \"cpu\", \"pipeline\": \"deferred\" "
        "and filter nearest or trilinear");
  return desc;
}

}  // namespace

LightVolume::LightVolume(const scene::LightsDesc& requested, const gl::ShaderLibrary& shaders)
    : desc_(decidedShade(decided(requested))) {
  const scene::LightsDesc& desc = desc_;
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSize);
  for (int n : desc.voxels) {
    if (n > maxSize) {
      throw InputError("lights.volume.voxels: a light volume of " + sizeText(desc) +
                       " is more than this GL allows (" + std::to_string(maxSize) +
                       " per axis); use fewer voxels or a larger lights.volume.voxel_size");
    }
  }
  const bool paper = desc.accumulate == scene::LightAccumulate::Paper;
  const bool atomic = desc.accumulate == scene::LightAccumulate::Atomic;
  if (desc.accumulate != scene::LightAccumulate::Cpu) {
    accumulate_ =
        gl::buildProgram(shaders,
                         {{gl::ShaderStage::Compute,
                           paper ? "lights_accumulate_paper.comp" : "lights_accumulate.comp"}},
                         "light accumulation");
  }
  if (atomic) {
    resolve_ = gl::buildProgram(shaders, {{gl::ShaderStage::Compute, "lights_resolve.comp"}},
                                "light resolve");
  }
  probe_ =
      gl::buildProgram(shaders, {{gl::ShaderStage::Compute, "lights_probe.comp"}}, "light probe");
  while (glGetError() != GL_NO_ERROR) {
  }
  colour_ = volumeTexture(desc, GL_RGBA16F);
  direction_ = volumeTexture(desc, GL_RGBA16F);
  if (atomic)
    for (gl::Texture& s : sums_) s = volumeTexture(desc, GL_R32I);
  if (glGetError() == GL_OUT_OF_MEMORY) {
    throw InputError("lights.volume.voxels: GL could not allocate a light volume of " +
                     sizeText(desc) +
                     "; use fewer voxels, a larger lights.volume.voxel_size or "
                     "\"accumulate\": \"cpu\" or \"paper\" (no integer sums)");
  }
  for (const gl::Texture* t : {&colour_, &direction_}) {
    glTextureParameteri(t->id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t->id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum w : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
      glTextureParameteri(t->id(), w, GL_CLAMP_TO_BORDER);
    const float zero[4] = {0, 0, 0, 0};
    glTextureParameterfv(t->id(), GL_TEXTURE_BORDER_COLOR, zero);
  }
  for (const gl::Program* p : {&accumulate_, &resolve_}) {
    if (p->id() == 0) continue;
    setVolumeUniforms(p->id(), desc);
  }
  if (const GLuint a = accumulate_.id()) {
    glProgramUniform3f(a, glGetUniformLocation(a, "u_attenuation"), desc.attenuation[0],
                       desc.attenuation[1], desc.attenuation[2]);
    glProgramUniform1f(a, glGetUniformLocation(a, "u_range"), desc.range);
  }
  lights_ = gl::Buffer::create();
  if (atomic) {
    overflow_ = gl::Buffer::create();
    glNamedBufferData(overflow_.id(), sizeof(GLuint), nullptr, GL_DYNAMIC_READ);
  }
  box_ = dirty_ = wholeVolume(desc);
}

void LightVolume::setFilter(scene::LightFilter filter, float tension, int oversampling) {
  desc_.filter = filter, desc_.tension = tension, desc_.oversampling = oversampling;
}

double LightVolume::update(const std::vector<sph::lights::LightParticle>& all,
                           const LightView* view) {
  const auto start = std::chrono::steady_clock::now();
  box_ = view ? viewVoxels(desc_, *view) : wholeVolume(desc_);
  if (desc_.accumulate == scene::LightAccumulate::Cpu) {
    scale_ = fixedScale(desc_), rescaled_ = false;  // 64-bit sums: no voxel can wrap
    accumulateOnCpu(all, view);  // culls the lights as it bins them: no copy of the kept ones
    glFinish();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  std::vector<sph::lights::LightParticle> inView;
  if (view) inView = lightsInView(desc_, all, *view, box_);
  const std::vector<sph::lights::LightParticle>& lights = view ? inView : all;
  lastLights_ = lights.size();
  if (lights.size() > capacity_) {
    capacity_ = lights.size();
    glNamedBufferData(lights_.id(),
                      static_cast<GLsizeiptr>(capacity_ * sizeof(sph::lights::LightParticle)),
                      nullptr, GL_DYNAMIC_DRAW);
    if (glGetError() == GL_OUT_OF_MEMORY)
      throw InputError("lights: GL could not allocate a buffer for " +
                       std::to_string(lights.size()) + " light particles");
  }
  if (!lights.empty()) {
    glNamedBufferSubData(
        lights_.id(), 0,
        static_cast<GLsizeiptr>(lights.size() * sizeof(sph::lights::LightParticle)), lights.data());
  }
  scale_ = fixedScale(desc_), rescaled_ = false;
  if (accumulate(lights.size(), scale_)) {
    // A voxel wrapped: this frame again at a scale where none can (coarser steps, same lights).
    scale_ = safeFixedScale(desc_, lights), rescaled_ = true;
    accumulate(lights.size(), scale_);
  }
  glFinish();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void LightVolume::accumulateOnCpu(const std::vector<sph::lights::LightParticle>& lights,
                                  const LightView* view) {
  std::optional<ViewCull> cull;
  if (view) cull.emplace(desc_, *view, box_);
  lights::accumulateOnCpu(desc_, lights, box_, scale_, cull ? &*cull : nullptr, cpuSums_);
  lastLights_ = cpuSums_.lights;
  stale_ = true;
  // Shaded on the CPU, the lighting pass samples no texture: uploaded only if one is sampled.
  if (desc_.shade != scene::LightShade::Cpu) upload();
}

void LightVolume::upload() const {
  stale_ = false;
  // Only the voxels the lights reached are uploaded (Fig. 11's lie in the lowest fifth of the
  // volume); every other voxel must read zero: what the last frame left outside them is cleared.
  const VoxelBox& b = cpuSums_.touched;
  if (!holds(b, dirty_)) {
    clearBox(colour_, dirty_, false);
    clearBox(direction_, dirty_, false);
  }
  dirty_ = b;
  if (b.empty()) return;
  for (const auto* t : {&colour_, &direction_}) {
    const auto& data = t == &colour_ ? cpuSums_.colour : cpuSums_.direction;
    glTextureSubImage3D(t->id(), 0, b.lo[0], b.lo[1], b.lo[2], b.hi[0] - b.lo[0], b.hi[1] - b.lo[1],
                        b.hi[2] - b.lo[2], GL_RGBA, GL_HALF_FLOAT, data.data());
  }
}

bool LightVolume::accumulate(std::size_t count, float scale) {
  const bool paper = desc_.accumulate == scene::LightAccumulate::Paper;
  // Outside this frame's box every voxel must read zero: clear what the last frame left there.
  // Inside it the paper's read-modify-write starts from zero; the atomic path's resolve writes
  // every voxel of the box, so its textures need no clear there (only its integer sums).
  for (const gl::Texture* t : {&colour_, &direction_}) {
    if (!sameBox(dirty_, box_)) clearBox(*t, dirty_, false);
    if (paper) clearBox(*t, box_, false);
  }
  dirty_ = box_;
  if (!paper) {
    for (gl::Texture& s : sums_) clearBox(s, box_, true);
    const GLuint clear = 0;
    glNamedBufferSubData(overflow_.id(), 0, sizeof clear, &clear);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, overflow_.id());
    for (const gl::Program* p : {&accumulate_, &resolve_})
      glProgramUniform1f(p->id(), glGetUniformLocation(p->id(), "u_fixedScale"), scale);
  }
  for (const gl::Program* p : {&accumulate_, &resolve_}) {
    if (p->id() == 0) continue;
    glProgramUniform3i(p->id(), glGetUniformLocation(p->id(), "u_boxLo"), box_.lo[0], box_.lo[1],
                       box_.lo[2]);
    glProgramUniform3i(p->id(), glGetUniformLocation(p->id(), "u_boxHi"), box_.hi[0] - 1,
                       box_.hi[1] - 1, box_.hi[2] - 1);
  }
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                  GL_SHADER_STORAGE_BARRIER_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, lights_.id());
  if (paper) {
    glBindImageTexture(0, colour_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA16F);
    glBindImageTexture(1, direction_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA16F);
  } else {
    for (GLuint k = 0; k < 6; ++k)
      glBindImageTexture(k, sums_[k].id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32I);
  }
  const GLuint a = accumulate_.id();
  glProgramUniform1ui(a, glGetUniformLocation(a, "u_count"), static_cast<GLuint>(count));
  glUseProgram(a);
  // GL guarantees 65,535 work groups per dispatch (llvmpipe allows no more): 4,194,240 lights of
  // 64; a larger frame goes in several dispatches (one more would fail and accumulate nothing).
  constexpr std::size_t kLightsPerDispatch = 65535 * 64;
  for (std::size_t first = 0; first < count; first += kLightsPerDispatch) {
    glProgramUniform1ui(a, glGetUniformLocation(a, "u_first"), static_cast<GLuint>(first));
    const std::size_t n = std::min(kLightsPerDispatch, count - first);
    glDispatchCompute(static_cast<GLuint>((n + 63) / 64), 1, 1);
  }
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                  GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint wrapped = 0;
  if (!paper && !box_.empty()) {
    glGetNamedBufferSubData(overflow_.id(), 0, sizeof wrapped, &wrapped);
    glBindImageTexture(6, colour_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glBindImageTexture(7, direction_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glUseProgram(resolve_.id());
    glDispatchCompute(static_cast<GLuint>((box_.hi[0] - box_.lo[0] + 3) / 4),
                      static_cast<GLuint>((box_.hi[1] - box_.lo[1] + 3) / 4),
                      static_cast<GLuint>((box_.hi[2] - box_.lo[2] + 3) / 4));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  glUseProgram(0);
  for (GLuint k = 0; k < 8; ++k) glBindImageTexture(k, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32I);
  return wrapped != 0;
}

bool LightVolume::shadesOnCpu() const {
  return desc_.shade == scene::LightShade::Cpu && desc_.filter != scene::LightFilter::Tricubic;
}

void LightVolume::shadeOnCpu(const frame::GBufferPixels& g, const Vec3& eye,
                             std::uint8_t* rgba) const {
  CpuShading(desc_, cpuSums_, terms).pixels(g, eye, rgba);
}

std::vector<Vec3> LightVolume::probeOnCpu(const std::vector<ProbePoint>& points,
                                          const Vec3& base) const {
  if (desc_.accumulate != scene::LightAccumulate::Cpu)
    throw InputError("lights.shade: the CPU shading needs \"accumulate\": \"cpu\"");
  const CpuShading shading(desc_, cpuSums_, terms);
  std::vector<Vec3> out(points.size());
  parallelForDynamic(points.size(), 1024, [&](std::size_t i) {
    out[i] = shading.at(points[i].position, points[i].normal, points[i].toEye, base);
  });
  return out;
}

std::vector<Vec3> LightVolume::shade(const std::vector<ProbePoint>& points,
                                     const Vec3& base) const {
  return shadesOnCpu() ? probeOnCpu(points, base) : probe(points, base);
}

void LightVolume::apply(GLuint p) const {
  // A program that samples the textures (llvmpipe drops unused samplers: -1 where the particle
  // lights' code is compiled out) needs this frame's sums in them.
  if (stale_ && (glGetUniformLocation(p, "u_lightColour") >= 0 ||
                 glGetUniformLocation(p, "u_lightDirection") >= 0))
    upload();
  glBindTextureUnit(kColourUnit, colour_.id());
  glBindTextureUnit(kDirectionUnit, direction_.id());
  auto loc = [&](const char* name) { return glGetUniformLocation(p, name); };
  glProgramUniform1i(p, loc("u_particleLights"), 1);
  glProgramUniform3f(p, loc("u_lightOrigin"), desc_.origin.x(), desc_.origin.y(), desc_.origin.z());
  glProgramUniform1f(p, loc("u_lightVoxel"), desc_.voxelSize);
  glProgramUniform3i(p, loc("u_lightVoxels"), desc_.voxels[0], desc_.voxels[1], desc_.voxels[2]);
  glProgramUniform1i(p, loc("u_lightFilter"), static_cast<int>(desc_.filter));
  glProgramUniform1f(p, loc("u_lightTension"), desc_.tension);
  glProgramUniform1i(p, loc("u_lightOversampling"), desc_.oversampling);
  glProgramUniform3f(p, loc("u_lightMaterial"), desc_.diffuse, desc_.specular, desc_.shininess);
  glProgramUniform1i(p, loc("u_lightTerms"), terms);
  glProgramUniform1f(p, loc("u_lightRoom"), desc_.roomLight);
}

std::vector<Vec3> LightVolume::probe(const std::vector<ProbePoint>& points,
                                     const Vec3& base) const {
  std::vector<float> packed(points.size() * 12, 0.0f);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      packed[12 * i + a] = points[i].position[a];
      packed[12 * i + 4 + a] = points[i].normal[a];
      packed[12 * i + 8 + a] = points[i].toEye[a];
    }
  }
  std::vector<Vec3> out(points.size(), Vec3::Zero());
  if (points.empty()) return out;
  gl::Buffer in = gl::Buffer::create(), result = gl::Buffer::create();
  glNamedBufferData(in.id(), static_cast<GLsizeiptr>(packed.size() * sizeof(float)), packed.data(),
                    GL_STATIC_DRAW);
  glNamedBufferData(result.id(), static_cast<GLsizeiptr>(points.size() * 16), nullptr,
                    GL_DYNAMIC_READ);
  const GLuint p = probe_.id();
  apply(p);
  glProgramUniform1ui(p, glGetUniformLocation(p, "u_count"), static_cast<GLuint>(points.size()));
  glProgramUniform3f(p, glGetUniformLocation(p, "u_probeBase"), base.x(), base.y(), base.z());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, result.id());
  glUseProgram(p);
  glDispatchCompute(static_cast<GLuint>((points.size() + 63) / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  std::vector<float> raw(points.size() * 4);
  glGetNamedBufferSubData(result.id(), 0, static_cast<GLsizeiptr>(raw.size() * sizeof(float)),
                          raw.data());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = {raw[4 * i], raw[4 * i + 1], raw[4 * i + 2]};
  return out;
}

namespace {
std::vector<std::array<float, 4>> readTexture(GLuint t, std::size_t voxels) {
  std::vector<std::array<float, 4>> out(voxels);
  gl::readTexture(t, GL_RGBA, GL_FLOAT, voxels * 16, out.data());
  return out;
}
}  // namespace

std::vector<std::array<float, 4>> LightVolume::readColour() const {
  if (stale_) upload();
  return readTexture(colour_.id(), desc_.voxelCount());
}
std::vector<std::array<float, 4>> LightVolume::readDirection() const {
  if (stale_) upload();
  return readTexture(direction_.id(), desc_.voxelCount());
}

}  // namespace sph::render::lights
