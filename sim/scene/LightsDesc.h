// The scene's `lights` section (docs/scene-format.md, "lights"; docs/lights.md): particles as
// point lights, gathered into two 3D textures (light colour, light direction) and sampled by the
// solids' and the water's shading (Kim & Lee 2020, seed 004; DESIGN.md, "Particle lights").
// Plain data; render/lights turns it into GL objects. No section, no light code runs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "sim/scene/EnumNames.h"
#include "sim/Types.h"

namespace sph::scene {

// Which particles glow (scene key lights.source).
enum class LightSource {
  Fluid,    // every fluid particle
  Emitter,  // lights.emitter: light particles drifting in a box, no fluid
};
constexpr const char* nameOf(LightSource v) {
  switch (v) {
    case LightSource::Fluid:
      return "fluid";
    case LightSource::Emitter:
      return "emitter";
  }
  return nullptr;
}

// How a particle's colour is chosen (lights.colour_by).
enum class LightColouring {
  Constant,  // lights.colour for every particle
  Speed,     // lights.colour (at rest) to lights.fast_colour (at lights.fast_speed and above)
};
constexpr const char* nameOf(LightColouring v) {
  switch (v) {
    case LightColouring::Constant:
      return "constant";
    case LightColouring::Speed:
      return "speed";
  }
  return nullptr;
}

// How the light textures are read at a shaded point (lights.filter; seed 004 section 6.1).
enum class LightFilter {
  Nearest,    // the voxel the point lies in
  Trilinear,  // the 2x2x2 voxel centres around it (GL's linear filter)
  Tricubic,   // the 4x4x4 around it, Catmull-Rom with lights.tension (the paper's "4x4x4")
};
constexpr const char* nameOf(LightFilter v) {
  switch (v) {
    case LightFilter::Nearest:
      return "nearest";
    case LightFilter::Trilinear:
      return "trilinear";
    case LightFilter::Tricubic:
      return "tricubic";
  }
  return nullptr;
}

// Where the particle lights are applied (lights.pipeline; seed 004 Fig. 11).
enum class LightPipeline {
  Forward,   // in each object's fragment (solids) or vertex (splats) shading
  Deferred,  // a G-buffer of the solids, then one full-screen lighting pass
};
constexpr const char* nameOf(LightPipeline v) {
  switch (v) {
    case LightPipeline::Forward:
      return "forward";
    case LightPipeline::Deferred:
      return "deferred";
  }
  return nullptr;
}

// How particles add into shared voxels (lights.accumulate).
enum class LightAccumulate {
  Atomic,  // fixed-point integer atomicAdd, then a resolve pass: exact, order-independent
  Paper,   // the paper's imageLoad + imageStore from every invocation at once: loses updates
  Cpu,     // the atomic path's sums gathered per z slice by OpenMP threads, then uploaded
  Auto,    // the scene's default: cpu where GL draws in software (llvmpipe: 7-10x faster,
           // docs/benchmarks.md), atomic on a GPU; decided when the volume is made
};
constexpr const char* nameOf(LightAccumulate v) {
  switch (v) {
    case LightAccumulate::Atomic:
      return "atomic";
    case LightAccumulate::Paper:
      return "paper";
    case LightAccumulate::Cpu:
      return "cpu";
    case LightAccumulate::Auto:
      return "auto";
  }
  return nullptr;
}

// Where the particle lights' Phong term is computed per pixel (lights.shade; docs/lights.md,
// "Shading on the CPU").
enum class LightShade {
  Gl,    // the lighting pass (or each surface's shader) samples the two 3D textures
  Cpu,   // deferred only: the CPU computes it from the G-buffer read back and the volume it
         // accumulated (render/lights/CpuShading.h); the lighting pass adds one 2D texture
  Auto,  // cpu where the volume is on the CPU anyway (accumulate "cpu", deferred, filter nearest
         // or trilinear), gl otherwise; decided when the volume is made
};
constexpr const char* nameOf(LightShade v) {
  switch (v) {
    case LightShade::Gl:
      return "gl";
    case LightShade::Cpu:
      return "cpu";
    case LightShade::Auto:
      return "auto";
  }
  return nullptr;
}

// Light particles that exist only as lights: `count` points placed uniformly at random in the
// box from `seed`, each drifting at `speed` in a random direction and wrapping around the box.
// Their positions at time t are a pure function of (seed, index, t), so caches need not store
// them (docs/lights.md, "Replay").
struct LightEmitterDesc {
  Aabb box;
  std::size_t count = 0;
  float speed = 0.2f;  // m/s
  std::uint32_t seed = 1;
};

struct LightsDesc {
  LightSource source = LightSource::Fluid;
  LightEmitterDesc emitter;               // source "emitter"
  Vec3 colour = Vec3(1.0f, 0.55f, 0.2f);  // linear RGB, times intensity
  float intensity = 1.0f;                 // the paper's colour alpha: weights the direction too
  LightColouring colouring = LightColouring::Constant;
  Vec3 fastColour = Vec3(0.3f, 0.6f, 1.0f);  // colour_by "speed": at fast_speed and above
  float fastSpeed = 1.0f;                    // m/s
  // 1 / (c + l d + q d^2), d in metres from the light (seed 004 eq. 1, with the parentheses the
  // text has and its pseudo-code lost), zero beyond `range` m.
  std::array<float, 3> attenuation = {1.0f, 0.0f, 1.0f};
  float range = 1.0f;  // m
  // The volume: voxels[i] cells of voxelSize m from `origin` (the paper: 1 m over 128^3).
  Vec3 origin = Vec3::Zero();
  float voxelSize = 1.0f;
  std::array<int, 3> voxels = {128, 128, 128};
  LightFilter filter = LightFilter::Trilinear;
  float tension = 0.0f;  // Catmull-Rom tension in [0, 1] (0: the classic spline)
  int oversampling = 1;  // samples per axis inside one voxel around the point (1 = off)
  LightPipeline pipeline = LightPipeline::Forward;
  LightAccumulate accumulate = LightAccumulate::Atomic;
  LightShade shade = LightShade::Auto;  // as the scene loader's default
  // Frustum culling (seed 004's future work): a frame drawn through a camera clears, accumulates
  // and resolves only the voxels its visible points may read, with only the lights that reach
  // them; the picture is the same (docs/lights.md, "Frustum culling").
  bool cull = true;
  // The surfaces' response to particle light (Phong, seed 004 section 5).
  float diffuse = 1.0f, specular = 0.5f, shininess = 16.0f;
  // The scene's own light and background are scaled by this (1: unchanged; 0.1: a dark room).
  float roomLight = 1.0f;
  double maxMemoryMiB = 2048;  // GL memory the volume may take (textures + accumulation buffer)

  Vec3 extent() const {
    return voxelSize * Vec3(static_cast<float>(voxels[0]), static_cast<float>(voxels[1]),
                            static_cast<float>(voxels[2]));
  }
  std::size_t voxelCount() const {
    return static_cast<std::size_t>(voxels[0]) * static_cast<std::size_t>(voxels[1]) *
           static_cast<std::size_t>(voxels[2]);
  }
  // GL bytes: two RGBA16F textures (8 B each) + the atomic path's six int32 sums (24 B; counted
  // for `auto` too, which is atomic on a GPU).
  double memoryBytes() const {
    const bool sums = accumulate == LightAccumulate::Atomic || accumulate == LightAccumulate::Auto;
    return static_cast<double>(voxelCount()) * (16.0 + (sums ? 24.0 : 0.0));
  }
};

}  // namespace sph::scene
