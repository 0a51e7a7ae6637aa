// The particle cloud the sim/ranks suites drive the halo with (tests/test_dist.cpp,
// tests/test_halo_places.cpp): a 1 x 0.3 x 0.3 m domain whose long side lies along `axis` (the
// slabs cut it), a dense block of water in its lower half and a sparse spray everywhere. The
// positions at step s are a function of the id, and every step moves most particles by up to
// 0.3 m along the long side, so they cross slab faces; the other fields are distinct per id, so
// a record that travels wrong shows (the positions are computed in one place, HaloCloud.cpp, so
// no caller's inlining contracts them differently). A `thin` cloud lies still in two cell planes
// across the long side, so a cut by particle counts leaves ranks without particles.
#pragma once

#include <cstdint>

#include "sim/Particles.h"
#include "sim/Types.h"

namespace sph::test {

constexpr std::uint32_t kCloud = 2500;
constexpr float kSupport = 0.04f;  // 25 cell planes along the long side

struct CloudShape {
  int axis = 0;  // the long side
  bool thin = false;
};

Aabb cloudDomain(CloudShape shape = {});
Vec3 cloudAt(std::uint32_t id, int step, CloudShape shape = {});
void placeCloud(Particles& f, int step, CloudShape shape = {});
// Particle `id` of the cloud at step 0 (its velocity, density, pressure and more from the id).
void appendCloudParticle(Particles& f, std::uint32_t id, CloudShape shape = {});
Particles fullCloud(CloudShape shape = {});

}  // namespace sph::test
