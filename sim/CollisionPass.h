// The one seam between the SPH step and an inter-particle collision method (DESIGN.md, "The CDT
// collision pass"). Implementations live in sim/ (CPU methods) and render/ (cdt-gl); the step
// calls apply() after integration and before boundary enforcement.
#pragma once

#include <cstddef>
#include <string>

#include "sim/Particles.h"

namespace sph {

struct CollisionContext {
  double time = 0;  // s, time at the end of the step
  double dt = 0;    // s, the step just integrated
  std::uint64_t step = 0;
};

class CollisionPass {
 public:
  virtual ~CollisionPass() = default;
  virtual std::string name() const = 0;
  // Detects and responds to collisions in place. Particle order is the neighbour-grid order of
  // this step; implementations must not keep indices across calls (use Particles::id).
  virtual void apply(Particles& particles, const CollisionContext& context) = 0;
};

}  // namespace sph
