// The light volume's accumulation on the CPU (lights.accumulate "cpu"; docs/lights.md): the same
// sums as the atomic compute shader (shaders/lights_accumulate.glsl, same float steps, the same
// fixed-point rounding), gathered per z slice of voxels by OpenMP threads so that no two threads
// add into one voxel, in 64-bit integers that cannot wrap, then converted as the resolve pass does
// (shaders/lights_resolve.comp). On llvmpipe the "GPU" is these same CPU cores behind a shader
// compiler and 32-bit image atomics; render/lights/LightVolume.cpp uploads the result.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "render/lights/LightCulling.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/LightsDesc.h"

namespace sph::render::lights {

// The two textures' values over `touched` (x fastest, then y, then z), RGBA per voxel as the
// textures' half floats (IEEE binary16 bits, see toHalf): colour (alpha 0) and direction (alpha
// 0), each light's terms rounded to steps of 1 / scale. Half floats, the textures' own format:
// the upload is a copy. Kept from frame to frame (its storage and the binning's are reused).
struct VoxelSums {
  // The voxels of the frame's box within range of a light it kept (the smallest box holding
  // them): every other voxel of the frame's box is zero, and is neither converted nor uploaded.
  VoxelBox touched;
  std::vector<std::array<std::uint16_t, 4>> colour, direction;
  std::size_t lights = 0;  // the lights the cull kept (all of them without one)
  // Scratch of the binning, kept with the sums so that a frame allocates nothing: per light the
  // voxels it reaches, and per z slice the lights that reach it with their x and y voxel ranges.
  // Both as few bytes as the sums need (12 and 36, not 24 and 48): at 1M lights the binning is
  // mostly moving them (docs/notes/2026-11-27-lights-fig11.md, "The binning passes made
  // lighter"). Voxels are counted from the box's lowest corner, in 16 bits (a box is at most
  // 2048 voxels a side, LightsDesc).
  struct Reach {
    std::array<std::uint16_t, 3> lo, hi;  // inclusive; lo[2] > hi[2] for a light that adds nothing
  };
  struct BinnedLight {
    std::array<float, 3> position;  // the light's, less its unused w
    std::array<float, 4> colour;
    std::array<std::uint16_t, 4> xy;  // x first, last, y first, last
  };
  std::vector<Reach> reachOf;
  std::vector<BinnedLight> binned;
};
// IEEE binary16 of `f`, rounded toward zero (F16C where the build has it): llvmpipe's own
// float-to-half conversion (the resolve pass's imageStore, a float upload) truncates so, and the
// "cpu" volume is then the "atomic" one texel for texel (tests/test_lights_cpu.cpp).
std::uint16_t toHalf(float f);
// The float IEEE binary16 `h` stands for, exactly (lights.shade "cpu" reads the sums so).
float fromHalf(std::uint16_t h);
// The sums of `lights` over the voxels of `box` into `out`; with a `cull`, only the lights it
// keeps (as the atomic path runs only lightsInView's).
void accumulateOnCpu(const scene::LightsDesc& desc,
                     const std::vector<sph::lights::LightParticle>& lights, const VoxelBox& box,
                     float scale, const ViewCull* cull, VoxelSums& out);

}  // namespace sph::render::lights
