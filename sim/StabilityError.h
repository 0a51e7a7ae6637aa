// Numerical blow-up (STYLE.md rule 10, third kind): the step, time and particle where the state
// stopped being physical, so the user can reproduce and look.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "sim/Types.h"

namespace sph {

class StabilityError : public std::runtime_error {
 public:
  enum class Kind { NonFinite, LeftDomain };
  StabilityError(Kind kind_, std::uint64_t step_, double time_, std::uint32_t particleId_,
                 const Vec3& position_, const Vec3& velocity_, const std::string& message)
      : std::runtime_error(message),
        kind(kind_),
        step(step_),
        time(time_),
        particleId(particleId_),
        position(position_),
        velocity(velocity_) {}
  Kind kind;
  std::uint64_t step;  // index of the step that produced the bad state (from 1)
  double time;         // s, simulated time at the end of that step
  std::uint32_t particleId;
  Vec3 position, velocity;
};

}  // namespace sph
