// The particle-light volume of seed 004 (Kim & Lee 2020; DESIGN.md, "Particle lights";
// docs/lights.md): two RGBA16F 3D textures over the scene's `lights.volume`, the sum of every
// light's attenuated colour and of its intensity-weighted direction per voxel, rebuilt by compute
// shaders from the lights of each frame and sampled by the surfaces' shading through
// shaders/extra_lights.glsl (nearest, trilinear or tricubic, optionally oversampled), or with
// lights.shade "cpu" evaluated on the CPU from the sums it accumulated there (CpuShading.h).
// Needs a current GL 4.5 context; exists only when a scene has `lights`.
#pragma once

#include <array>
#include <vector>

#include "render/frame/ExtraLights.h"
#include "render/gl/GlHandle.h"
#include "render/gl/ShaderLibrary.h"
#include "render/lights/CpuAccumulation.h"
#include "render/lights/LightCulling.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/LightsDesc.h"

namespace sph::render::lights {

// The atomic path's fixed point: a voxel's sums are integers in steps of 1 / fixedScale, and
// fixedScale = kFixedSteps / lights.intensity, so one light's full colour is kFixedSteps steps and
// a voxel's sum fits an int32 up to 2^31 / kFixedSteps = 131,072 full-intensity lights at
// distance 0. A frame that crowds more into one voxel is detected (an add that wraps sets a flag)
// and accumulated again at safeFixedScale, where no voxel can wrap whatever the lights' places.
inline constexpr float kFixedSteps = 16384.0f;
float fixedScale(const scene::LightsDesc& desc);
// The largest scale at which every light of `lights` in one voxel, each at its brightest (distance
// 0: colour / attenuation constant; direction: intensity), still fits an int32, rounding included.
float safeFixedScale(const scene::LightsDesc& desc,
                     const std::vector<sph::lights::LightParticle>& lights);

// A shading point for probe(): world position, outward unit normal, unit vector to the eye.
struct ProbePoint {
  Vec3 position, normal, toEye;
};

class LightVolume final : public frame::ExtraLights {
 public:
  // Allocates the textures (and the atomic path's six int32 images). A volume GL cannot hold
  // (larger than GL_MAX_3D_TEXTURE_SIZE, or GL_OUT_OF_MEMORY) throws InputError naming its size
  // and the keys to change.
  explicit LightVolume(const scene::LightsDesc& desc,
                       const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());

  // Clears the volume and accumulates `lights` into it (desc().accumulate: `auto` is decided
  // when the volume is made); waits for the GPU.
  // Returns the seconds it took (culling and upload included). With a `view` (lights.cull), only
  // the voxels a point seen through it may read are cleared, accumulated and resolved, and only
  // the lights that reach them run (LightCulling.h); every other voxel reads zero.
  double update(const std::vector<sph::lights::LightParticle>& lights,
                const LightView* view = nullptr);

  // Binds the textures to units 6 and 7 and sets the hook's uniforms on `program`.
  void apply(GLuint program) const override;
  // lights.pipeline "deferred": the frame's opaque surfaces are lit in one full-screen pass.
  bool deferred() const override { return desc_.pipeline == scene::LightPipeline::Deferred; }
  // lights.shade "cpu" (desc().shade, `auto` decided when the volume is made; CpuShading.h):
  // the lighting pass's term computed on the CPU from the last update's sums. A filter set to
  // tricubic since (compare's) goes back to the GL path.
  bool shadesOnCpu() const override;
  void shadeOnCpu(const frame::GBufferPixels& g, const Vec3& eye,
                  std::uint8_t* rgba) const override;

  // Which Phong terms apply() switches on (bit 0 diffuse, bit 1 specular; the error figures).
  int terms = 3;
  // The filter settings may change between frames (compare draws each filter from one volume).
  void setFilter(scene::LightFilter filter, float tension, int oversampling);

  // The shading term of extra_lights.glsl at each point, on the GPU (base colour `base`).
  std::vector<Vec3> probe(const std::vector<ProbePoint>& points, const Vec3& base) const;
  // The same term as lights.shade "cpu" computes it (CpuShading.h; accumulate "cpu" only).
  std::vector<Vec3> probeOnCpu(const std::vector<ProbePoint>& points, const Vec3& base) const;
  // What a frame shades with: probeOnCpu where shadesOnCpu(), else probe (compare's figures).
  std::vector<Vec3> shade(const std::vector<ProbePoint>& points, const Vec3& base) const;

  // The textures' contents, RGBA per voxel, x fastest (tests, benchmarks).
  std::vector<std::array<float, 4>> readColour() const;
  std::vector<std::array<float, 4>> readDirection() const;

  const scene::LightsDesc& desc() const { return desc_; }
  // The fixed-point scale of the last update (atomic), and whether it had to be lowered from
  // fixedScale(desc()) because a voxel would have wrapped.
  float lastFixedScale() const { return scale_; }
  bool lastRescaled() const { return rescaled_; }
  // The lights and the voxels the last update accumulated (all of them without a view).
  std::size_t lastLights() const { return lastLights_; }
  const VoxelBox& lastBox() const { return box_; }

 private:
  scene::LightsDesc desc_;
  gl::Program accumulate_, resolve_, probe_;
  gl::Texture colour_, direction_;
  std::array<gl::Texture, 6> sums_;
  gl::Buffer lights_, overflow_;
  std::size_t capacity_ = 0;
  float scale_ = 0;
  bool rescaled_ = false;
  std::size_t lastLights_ = 0;
  // The voxels of this frame, and those the textures may hold non-zero values in (the last
  // frame's box, or with "cpu" the voxels it uploaded; the whole volume before the first, its
  // storage being undefined).
  // Mutable: with lights.shade "cpu" the sums are uploaded only when a program that samples the
  // textures is applied (the forward water over a deferred frame, probe) or they are read.
  mutable VoxelBox dirty_;
  VoxelBox box_;
  VoxelSums cpuSums_;           // "cpu": the last frame's sums, their storage reused
  mutable bool stale_ = false;  // "cpu": cpuSums_ not uploaded yet
  // "cpu": the voxels cpuSums_ holds into the two textures, zero where the last upload left any.
  void upload() const;
  // Clears the volume and accumulates the uploaded `count` lights at fixed-point `scale` into
  // box_; returns whether a voxel's sum wrapped (atomic only).
  bool accumulate(std::size_t count, float scale);
  // lights.accumulate "cpu": the sums of `lights` (those `view` keeps, if any) over box_ on the
  // CPU (CpuAccumulation.h); only the voxels they reach are uploaded into the two textures.
  void accumulateOnCpu(const std::vector<sph::lights::LightParticle>& lights,
                       const LightView* view);
};

}  // namespace sph::render::lights
