// lights.shade "cpu" (docs/lights.md, "Shading on the CPU"): the particle lights' Phong term of
// shaders/extra_lights.glsl (particleLight) computed on the CPU, from the half-float texels that
// lights.accumulate "cpu" gathered (CpuAccumulation.h) - the very values GL samples from the two
// 3D textures - for each pixel of the deferred G-buffer read back, added to the pixel's other
// lighting and sRGB-encoded there, so the lighting pass only copies. On llvmpipe the lighting
// pass's two trilinear 3D-texture fetches a pixel were ~60 CPU ms of Fig. 11's frame
// (docs/benchmarks.md, issue 14); here they are eight 8-byte loads each, with shared weights.
// Filters nearest and trilinear, with oversampling; tricubic stays on the GL path.
#pragma once

#include <cstddef>
#include <cstdint>

#include "render/lights/CpuAccumulation.h"
#include "render/splat/ExtraLights.h"
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
  // Per pixel of a G-buffer read back (ExtraLights.h; the world position from its depth), the lit
  // colour plus the term seen from `eye`, clamped and sRGB-encoded (Srgb8Table.h) into `rgba`
  // (RGBA8, alpha 255; all zero where no surface was drawn). OpenMP over rows.
  void pixels(const splat::GBufferPixels& g, const Vec3& eye, std::uint8_t* rgba) const;

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
