// lights.shade "cpu" (docs/lights.md, "Shading on the CPU"): the particle lights' Phong term of
// shaders/extra_lights.glsl (particleLight) computed on the CPU, from the half-float texels that
// lights.accumulate "cpu" gathered (CpuAccumulation.h) - the very values GL samples from the two
// 3D textures - for each pixel of the deferred G-buffer read back. On llvmpipe the lighting
// pass's two trilinear 3D-texture fetches a pixel were ~60 CPU ms of Fig. 11's frame
// (docs/benchmarks.md, issue 14); here they are eight 8-byte loads each, with shared weights.
// Filters nearest and trilinear, with oversampling; tricubic stays on the GL path.
#pragma once

#include <cstddef>
#include <cstdint>

#include "render/lights/CpuAccumulation.h"
#include "sim/LightsDesc.h"
#include "sim/Types.h"

namespace sph::render::lights {

class CpuShading {
 public:
  // `sums` must outlive this and hold the volume's last frame (every voxel outside sums.touched
  // reads zero, as the textures do). `terms`: bit 0 diffuse, bit 1 specular (LightVolume::terms).
  CpuShading(const LightsDesc& desc, const VoxelSums& sums, int terms = 3);

  // particleLight(base, position, n, toEye) at one point.
  Vec3 at(const Vec3& position, const Vec3& n, const Vec3& toEye, const Vec3& base) const;
  // Per pixel of a G-buffer of `count` pixels (RGBA each: world position with alpha 1 where a
  // surface was drawn, unit normal, albedo as half floats), the term seen from `eye` into `rgba`
  // (alpha 0; all zero where no surface was drawn). OpenMP over rows of 1,024 pixels.
  void pixels(std::size_t count, const float* position, const float* normal,
              const std::uint16_t* albedo, const Vec3& eye, float* rgba) const;

 private:
  const LightsDesc& desc_;
  const VoxelSums& sums_;
  int terms_;
  int wholeShininess_;  // desc.shininess where it is a whole number (power() squares), else 0
  // at(), with the vector to the eye found from `eye` only where it is needed (toEye null).
  Vec3 term(const Vec3& position, const Vec3& n, const Vec3* toEye, const Vec3& eye,
            const Vec3& base) const;
  float power(float x) const;  // x^shininess
  // The colour and direction textures through desc_'s filter at voxel coordinate g.
  void sample(const float g[3], float colour[4], float direction[4]) const;
  void filtered(const float g[3], float colour[4], float direction[4]) const;
};

}  // namespace sph::render::lights
