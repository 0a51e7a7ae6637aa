// lights.shade "cpu" (docs/lights.md, "Shading on the CPU"): the particle lights' Phong term of
// shaders/extra_lights.glsl (particleLight) computed on the CPU, from the half-float texels that
// lights.accumulate "cpu" gathered (CpuAccumulation.h) - the very values GL samples from the two
// 3D textures - for each pixel of the deferred G-buffer read back, added to the pixel's other
// lighting and sRGB-encoded there, so the lighting pass only copies. On llvmpipe the lighting
// pass's two trilinear 3D-texture fetches a pixel were ~60 CPU ms of Fig. 11's frame
// (docs/notes/2026-11-27-lights-fig11.md, "the draw profiled"); here the trilinear filter is four
// loads of a pair of texels
// along x from each texture, converted and weighted 16 floats at a time (AVX-512; 8 with AVX2),
// and the Phong terms run over a row's lit pixels in SIMD lanes (docs/lights.md says how).
// Filters nearest and trilinear, with oversampling; tricubic stays on the GL path.
//
// Every path (AVX-512, AVX2, plain C++) does the same float operations in the same order, and
// this file is built without contracting a * b + c into FMAs (render/lights/CMakeLists.txt): a
// pixel whose position the G-buffer holds gets at()'s term at that position, the same 8-bit
// colour on every build (tests/test_lights_shade.cpp). A position rebuilt from the depth takes
// its voxel coordinate as (p - origin) * (1 / voxel) rather than at()'s / voxel: within an ulp.
#pragma once

#include <cstddef>
#include <cstdint>

#include "render/frame/ExtraLights.h"
#include "render/lights/CpuAccumulation.h"
#include "sim/Types.h"
#include "sim/scene/LightsDesc.h"

namespace sph::render::lights {

class CpuShading {
 public:
  // `sums` must outlive this and hold the volume's last frame (every voxel outside sums.touched
  // reads zero, as the textures do). `terms`: bit 0 diffuse, bit 1 specular (LightVolume::terms).
  CpuShading(const scene::LightsDesc& desc, const VoxelSums& sums, int terms = 3);

  // particleLight(base, position, n, toEye) at one point.
  Vec3 at(const Vec3& position, const Vec3& n, const Vec3& toEye, const Vec3& base) const;
  // Per pixel of a G-buffer read back (ExtraLights.h; the world position from its depth, in
  // float, unless g.position is given), the lit colour plus the term seen from `eye` (the vector
  // to it as toEye() gives it), clamped and sRGB-encoded (Srgb8Table.h) into `rgba` (RGBA8, alpha
  // 255; all zero where no surface was drawn). OpenMP over rows.
  void pixels(const frame::GBufferPixels& g, const Vec3& eye, std::uint8_t* rgba) const;
  // The unit vector from `position` to `eye` as pixels() finds it (tests compare with at()).
  static Vec3 toEye(const Vec3& eye, const Vec3& position);

  // One row's lit pixels, structure of arrays (pixels() keeps one a thread; at() one of one).
  struct Run;

 private:
  const scene::LightsDesc& desc_;
  const VoxelSums& sums_;
  int terms_;
  int wholeShininess_;  // desc.shininess where it is a whole number (power by squaring), else 0
  // The colour and direction textures through desc_'s filter at voxel coordinate g.
  void sample(const float g[3], float colour[4], float direction[4]) const;
  void filtered(const float g[3], float colour[4], float direction[4]) const;
  // The linear filter's eight texels from the lower voxel centre i and the fraction f past it.
  void trilinear(const int i[3], const float f[3], float colour[4], float direction[4]) const;
  // trilinear() where some of the eight lie outside the box (read zero).
  void onFaces(const int i[3], const float wyz[4], const float wx[2], float colour[4],
               float direction[4]) const;
  // The Phong terms of the first `count` pixels of `run`, from their sampled colour and direction.
  void phong(Run& run, std::size_t count) const;
};

}  // namespace sph::render::lights
