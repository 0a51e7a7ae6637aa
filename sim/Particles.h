// The fluid state as a structure of arrays (STYLE.md rule 3): each per-particle quantity is one
// contiguous array so passes stream through memory and vectorise. Every array is listed once, in
// fields(); forEachField(), and through it resize, append and permute, walk that list, so a field
// added to the struct but not to the list is caught by the static_assert below (and by
// tests/test_particles.cpp). The cache's list of datasets is checked against it at compile time
// (io/cache/CacheFormat.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

#include "sim/Types.h"

namespace sph {

struct Particles {
  // Position (m).
  std::vector<float> x, y, z;
  // Velocity (m/s).
  std::vector<float> vx, vy, vz;
  // Acceleration of the last force evaluation (m/s^2).
  std::vector<float> ax, ay, az;
  // SPH density (kg/m^3) and pressure (Pa).
  std::vector<float> rho, p;
  // Cooldown of the CDT collision response (s); a particle may collide again once it is < 0
  // (seed 000, section 3.2, a_CollideTime).
  std::vector<float> collideTime;
  // Stable identity: survives sorting, written to caches (uint32).
  std::vector<std::uint32_t> id;

  static constexpr int kFieldCount = 13;

  // Every array, as member pointers, in the order of the cache's datasets.
  static constexpr auto fields() {
    return std::make_tuple(&Particles::x, &Particles::y, &Particles::z, &Particles::vx,
                           &Particles::vy, &Particles::vz, &Particles::ax, &Particles::ay,
                           &Particles::az, &Particles::rho, &Particles::p, &Particles::collideTime,
                           &Particles::id);
  }
  // Calls f(array) for every array, in fields() order.
  template <class F>
  void forEachField(F&& f) {
    std::apply([&](auto... member) { (f(this->*member), ...); }, fields());
  }
  template <class F>
  void forEachField(F&& f) const {
    std::apply([&](auto... member) { (f(this->*member), ...); }, fields());
  }

  std::size_t size() const { return x.size(); }
  bool empty() const { return x.empty(); }
  void resize(std::size_t n);
  void reserve(std::size_t n);
  void clear() { resize(0); }

  // Appends one particle at rest density and zero pressure/acceleration.
  void append(const Vec3& position, const Vec3& velocity, std::uint32_t particleId,
              float restDensity);

  // Reorders every field so that new[i] = old[order[i]]. `scratch` is reused between calls so a
  // sort every step allocates nothing.
  void permute(const std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& scratch);

  // Every field becomes from's at the indices `at`: new[i] = from[at[i]], at.size() particles.
  void assignFrom(const Particles& from, const std::vector<std::uint32_t>& at);

  Vec3 position(std::size_t i) const { return {x[i], y[i], z[i]}; }
  Vec3 velocity(std::size_t i) const { return {vx[i], vy[i], vz[i]}; }
  void setPosition(std::size_t i, const Vec3& v) { x[i] = v.x(), y[i] = v.y(), z[i] = v.z(); }
  void setVelocity(std::size_t i, const Vec3& v) { vx[i] = v.x(), vy[i] = v.y(), vz[i] = v.z(); }
};

// A field added to Particles must be added to fields() and kFieldCount too.
static_assert(sizeof(std::vector<float>) == sizeof(std::vector<std::uint32_t>));
static_assert(sizeof(Particles) == Particles::kFieldCount * sizeof(std::vector<float>),
              "Particles has a field that fields() does not list");
static_assert(std::tuple_size_v<decltype(Particles::fields())> == Particles::kFieldCount,
              "kFieldCount is not the length of fields()");

}  // namespace sph
