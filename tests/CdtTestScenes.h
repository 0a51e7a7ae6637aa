// Particle sets shared by the CDT tests: random particles in front of a collision camera, dense
// enough that many pairs are within the collision range and several share texels.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>

#include "sim/scene/CollisionDesc.h"
#include "sim/Particles.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::test {

// n particles uniformly in the cube [-half, half]^3 with random velocities (m/s), accelerations
// around gravity, cooldowns in [-0.1, 0.05] s (some still cooling down) and shuffled ids.
inline Particles randomParticles(std::size_t n, float half, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-half, half), vel(-1.0f, 1.0f), acc(-0.5f, 0.5f),
      cool(-0.1f, 0.05f);
  Particles p;
  std::vector<std::uint32_t> ids(n);
  std::iota(ids.begin(), ids.end(), 7u);
  std::shuffle(ids.begin(), ids.end(), rng);
  for (std::size_t i = 0; i < n; ++i) {
    p.append(Vec3(pos(rng), pos(rng), pos(rng)), Vec3(vel(rng), vel(rng), vel(rng)), ids[i],
             1000.0f);
    p.ax[i] = acc(rng), p.ay[i] = -9.81f + acc(rng), p.az[i] = acc(rng);
    p.collideTime[i] = cool(rng);
  }
  return p;
}

// A collision section looking at the origin from +z (3 m), 128^2 texels.
inline scene::CollisionDesc testCollision() {
  scene::CollisionDesc c;
  c.method = scene::CollisionMethod::CdtCpu;
  c.range = 0.03f;
  c.resolution = {128, 128};
  c.camera = scene::CdtCameraMode::Fixed;
  c.hasPose = true;
  c.pose.position = Vec3(0.3f, 0.4f, 3.0f);
  c.pose.target = Vec3(0, 0, 0);
  c.pose.fovYDegrees = 45;
  c.pose.near = 0.5f;
  c.pose.far = 10;
  return c;
}

}  // namespace sph::test
