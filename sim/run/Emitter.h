// A nozzle that pours fluid (DESIGN.md, "Emitters"): a disc of particles on a square lattice of
// the particle spacing, perpendicular to the direction, released layer after layer so that
// consecutive layers are one spacing apart along the jet. The nozzle stands for the end of a pipe:
// while it pours, the water within one kernel support of its disc moves at the nozzle's velocity.
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
  // `support`: the kernel's support radius (m), the length of the pipe's end that guide() holds.
  Emitter(const scene::EmitterDesc& desc, float spacing, float support);

  // Releases the layers due over a step of `dt` that ends at `time` (s). New particles get ids
  // from `nextId` onward and are appended to `fluid`. Returns how many were added.
  std::size_t emit(double time, double dt, Particles& fluid, std::uint32_t& nextId,
                   float restDensity);

  // After emit() for the same step, if the nozzle poured in it (within its window and not yet
  // spent when the step began, so the pipe's end still holds in the step that releases the last
  // layer): sets the velocity of every particle in the pipe's end (the disc's cylinder, from one
  // spacing behind the disc to one support ahead of it) to the nozzle's, and its acceleration to 0,
  // so that the step moves it at that velocity. Without it the newest layers are free, and a
  // disturbance that reaches them grows: a layer released one spacing behind a slowed one overlaps
  // it, the pressure throws the pair apart, one of them backwards out of the nozzle (the jug pour
  // under DFSPH spilled a hundred particles a second that way, beside its cup).
  void guide(Particles& fluid) const;

  const EmitterState& state() const { return state_; }
  void setState(const EmitterState& s) { state_ = s; }
  // Offsets of one layer's particles from the nozzle centre (m); empty if the disc is smaller
  // than one particle.
  const std::vector<Vec3>& layer() const { return layer_; }

 private:
  scene::EmitterDesc desc_;
  float spacing_;
  float support_;
  Vec3 direction_;
  std::vector<Vec3> layer_;
  EmitterState state_;
  bool pouring_ = false;  // emit()'s step poured: set by every emit(), so not part of the state
};

}  // namespace sph::run
