#include "tests/HaloCloud.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

namespace sph::test {

Aabb cloudDomain(CloudShape shape) {
  Vec3 hi(0.3f, 0.3f, 0.3f);
  hi[shape.axis] = 1.0f;
  return {Vec3(0, 0, 0), hi};
}

Vec3 cloudAt(std::uint32_t id, int step, CloudShape shape) {
  std::mt19937 rng(id * 7919u + 13u);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const bool spray = id % 5 == 0;
  Vec3 p(spray ? u(rng) : 0.5f * u(rng), (spray ? 0.3f : 0.15f) * u(rng), 0.3f * u(rng));
  if (shape.thin) {
    p.x() = 0.49f + 0.06f * u(rng);  // planes 12 and 13 of kSupport
  } else {
    const float shift = 0.3f * std::sin(0.37f * static_cast<float>(id) + 1.3f * step);
    p.x() = std::clamp(p.x() + (step == 0 ? 0.0f : shift), 0.0f, 0.999f);
  }
  std::swap(p.x(), p[shape.axis]);
  return p;
}

void placeCloud(Particles& f, int step, CloudShape shape) {
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Vec3 p = cloudAt(f.id[i], step, shape);
    f.x[i] = p.x(), f.y[i] = p.y(), f.z[i] = p.z();
  }
}

void appendCloudParticle(Particles& f, std::uint32_t id, CloudShape shape) {
  f.append(cloudAt(id, 0, shape), Vec3(0.001f * id, -0.002f * id, 0.5f), id, 1000.0f + 0.25f * id);
  f.p.back() = 3.0f * id, f.ax.back() = -1.0f * id, f.collideTime.back() = 0.125f * id;
}

Particles fullCloud(CloudShape shape) {
  Particles f;
  for (std::uint32_t id = 0; id < kCloud; ++id) appendCloudParticle(f, id, shape);
  return f;
}

}  // namespace sph::test
