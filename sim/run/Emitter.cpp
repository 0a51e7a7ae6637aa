#include "sim/run/Emitter.h"

#include <cmath>

#include "sim/Parallel.h"

namespace sph::run {

Emitter::Emitter(const scene::EmitterDesc& desc, float spacing, float support)
    : desc_(desc), spacing_(spacing), support_(support), direction_(desc.direction.normalized()) {
  const Vec3 helper = std::abs(direction_.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitZ();
  const Vec3 t1 = direction_.cross(helper).normalized(), t2 = direction_.cross(t1);
  // Lattice points (including the centre) within the radius.
  const int n = static_cast<int>(std::floor(desc.radius / spacing));
  for (int k = -n; k <= n; ++k) {
    for (int i = -n; i <= n; ++i) {
      const float u = i * spacing, w = k * spacing;
      if (u * u + w * w <= desc.radius * desc.radius * (1 + 1e-6f))
        layer_.push_back(u * t1 + w * t2);
    }
  }
}

std::size_t Emitter::emit(double time, double dt, Particles& fluid, std::uint32_t& nextId,
                          float restDensity) {
  const bool open = !layer_.empty() && time > desc_.start && time - dt < desc_.stop;
  pouring_ = open && !(desc_.maxParticles && state_.emitted + layer_.size() > desc_.maxParticles);
  if (!open) return 0;
  const double active = std::min(time, desc_.stop) - std::max(time - dt, desc_.start);
  if (!state_.started) {
    state_.started = true;
    state_.travelled = spacing_;  // the first layer leaves the nozzle at once
  } else {
    state_.travelled += desc_.speed * active;
  }
  std::size_t added = 0;
  const Vec3 velocity = desc_.speed * direction_;
  while (state_.travelled >= spacing_) {
    if (desc_.maxParticles && state_.emitted + layer_.size() > desc_.maxParticles) {
      state_.travelled = 0;  // the nozzle is spent; stop accumulating
      break;
    }
    state_.travelled -= spacing_;
    const Vec3 centre = desc_.position + static_cast<float>(state_.travelled) * direction_;
    for (const Vec3& offset : layer_) {
      fluid.append(centre + offset, velocity, nextId++, restDensity);
      ++added;
    }
    state_.emitted += layer_.size();
  }
  return added;
}

void Emitter::guide(Particles& fluid) const {
  if (!pouring_) return;
  const Vec3 velocity = desc_.speed * direction_;
  const float reach = desc_.radius + 0.5f * spacing_;
  parallelFor(fluid.size(), [&](std::size_t i) {
    const Vec3 d = fluid.position(i) - desc_.position;
    const float along = d.dot(direction_);
    if (along < -spacing_ || along > support_) return;
    if ((d - along * direction_).squaredNorm() > reach * reach) return;
    fluid.setVelocity(i, velocity);
    fluid.ax[i] = 0, fluid.ay[i] = 0, fluid.az[i] = 0;
  });
}

}  // namespace sph::run
