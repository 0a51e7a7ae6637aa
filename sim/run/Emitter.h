// A nozzle that pours fluid (DESIGN.md, "Emitters"): a disc of particles on a square lattice of
// the particle spacing, perpendicular to the direction, released layer after layer so that
// consecutive layers are one spacing apart along the jet.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/Particles.h"
#include "sim/scene/Scene.h"

namespace sph::run {

// What must be saved to resume an emitter exactly.
struct EmitterState {
  double travelled = 0;       // m the newest layer has moved since it was released
  std::uint64_t emitted = 0;  // particles released so far
  bool started = false;
};

class Emitter {
 public:
  Emitter(const scene::EmitterDesc& desc, float spacing);

  // Releases the layers due over a step of `dt` that ends at `time` (s). New particles get ids
  // from `nextId` onward and are appended to `fluid`. Returns how many were added.
  std::size_t emit(double time, double dt, Particles& fluid, std::uint32_t& nextId,
                   float restDensity);

  const EmitterState& state() const { return state_; }
  void setState(const EmitterState& s) { state_ = s; }
  // Offsets of one layer's particles from the nozzle centre (m); empty if the disc is smaller
  // than one particle.
  const std::vector<Vec3>& layer() const { return layer_; }

 private:
  scene::EmitterDesc desc_;
  float spacing_;
  Vec3 direction_;
  std::vector<Vec3> layer_;
  EmitterState state_;
};

}  // namespace sph::run
