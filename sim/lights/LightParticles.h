// The point lights of a scene's `lights` section at one moment (seed 004): the fluid's particles,
// or the drifting particles of lights.emitter. Plain data for render/lights (GPU volume) and its
// CPU exact reference. No OpenGL here.
#pragma once

#include <array>
#include <vector>

#include "sim/scene/LightsDesc.h"
#include "sim/Particles.h"
#include "sim/scene/Scene.h"
#include "sim/scene/Solid.h"

namespace sph::lights {

// Laid out as the GLSL struct LightParticle (shaders/lights_common.glsl): std430, 32 bytes.
struct LightParticle {
  std::array<float, 4> position;  // m, w unused
  std::array<float, 4> colour;    // colour * intensity (rgb), intensity (a)
};
static_assert(sizeof(LightParticle) == 32);

// The lights at simulated time `time` (s). Source "fluid": one per particle of `fluid`, coloured
// by desc (colour_by speed uses its velocity); source "emitter": desc.emitter's drifting points,
// a pure function of (seed, index, time), less those inside any of `solids` (fireflies do not fly
// through walls), `fluid` unused.
std::vector<LightParticle> lightParticles(const scene::LightsDesc& desc, const Particles& fluid,
                                          double time,
                                          const std::vector<scene::Solid>& solids = {});
// The solids of `scene` as lights see them (its boundaries, walls as thick as the boundary
// particles' layers).
std::vector<scene::Solid> lightSolids(const scene::Scene& scene);

// Emitter light i's position at time t: uniform in the box from a hash of (seed, i), moving at
// `speed` m/s in a direction from the same hash, wrapped periodically into the box.
Vec3 emitterLightPosition(const scene::LightEmitterDesc& e, std::size_t i, double time);

// 1 / (c + l d + q d^2) for d <= range, else 0 (seed 004 eq. 1 with its parentheses).
inline float lightAttenuation(const scene::LightsDesc& d, float distance) {
  if (distance > d.range) return 0.0f;
  return 1.0f /
         (d.attenuation[0] + d.attenuation[1] * distance + d.attenuation[2] * distance * distance);
}

}  // namespace sph::lights
