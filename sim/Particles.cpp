#include "sim/Particles.h"

#include <cstring>

#include "sim/Assert.h"
#include "sim/Parallel.h"

namespace sph {

void Particles::resize(std::size_t n) {
  forEachField([n](auto& field) { field.resize(n); });
}

void Particles::reserve(std::size_t n) {
  forEachField([n](auto& field) { field.reserve(n); });
}

void Particles::append(const Vec3& position, const Vec3& velocity, std::uint32_t particleId,
                       float restDensity) {
  x.push_back(position.x()), y.push_back(position.y()), z.push_back(position.z());
  vx.push_back(velocity.x()), vy.push_back(velocity.y()), vz.push_back(velocity.z());
  ax.push_back(0), ay.push_back(0), az.push_back(0);
  rho.push_back(restDensity), p.push_back(0);
  collideTime.push_back(-1.0f);
  id.push_back(particleId);
}

void Particles::permute(const std::vector<std::uint32_t>& order,
                        std::vector<std::uint32_t>& scratch) {
  const std::size_t n = size();
  SPH_ASSERT(order.size() == n);
  if (n == 0) return;  // empty fields' data() may be null, which memcpy must not be given
  scratch.resize(n);
  // Every field is 4 bytes wide, so one uint32 scratch array serves them all.
  forEachField([&](auto& field) {
    static_assert(sizeof(field[0]) == sizeof(std::uint32_t));
    auto* src = field.data();
    std::uint32_t* dst = scratch.data();
    parallelFor(n, [&](std::size_t i) { std::memcpy(&dst[i], &src[order[i]], 4); });
    std::memcpy(src, dst, n * 4);
  });
}

void Particles::assignFrom(const Particles& from, const std::vector<std::uint32_t>& at) {
  resize(at.size());
  std::apply(
      [&](auto... member) {
        ((parallelFor(at.size(),
                      [&](std::size_t i) { (this->*member)[i] = (from.*member)[at[i]]; })),
         ...);
      },
      fields());
}

}  // namespace sph
