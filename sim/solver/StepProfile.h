// Wall time spent in each pass of the step (STYLE.md rule 1): accumulated over a run, printed by
// `sphsplat run --verbose` and used for the per-pass split in docs/benchmarks.md.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

namespace sph::solver {

enum class Pass : int {
  Emit,
  Sort,
  Density,
  Factor,      // DFSPH: the density, the per-particle factor and the stored pairs (one search)
  Divergence,  // DFSPH: the divergence-free solver
  Pressure,    // WCSPH: the equation of state; DFSPH: the constant-density solver
  Forces,
  Integrate,
  Collide,
  Boundaries,
  Guard,
  Exchange,  // a distributed run's re-cut, migration and ghosts (sim/ranks/Halo.h)
  Count
};

inline const char* passName(Pass p) {
  static constexpr const char* names[] = {"emit",       "sort",       "density", "factor",
                                          "divergence", "pressure",   "forces",  "integrate",
                                          "collide",    "boundaries", "guard",   "exchange"};
  return names[static_cast<int>(p)];
}

struct StepProfile {
  std::array<double, static_cast<int>(Pass::Count)> seconds{};  // s per pass, summed
  std::uint64_t steps = 0;
  std::uint64_t particleSteps = 0;  // sum over steps of the fluid particle count

  double total() const {
    double t = 0;
    for (double s : seconds) t += s;
    return t;
  }
  double& operator[](Pass p) { return seconds[static_cast<int>(p)]; }
  double operator[](Pass p) const { return seconds[static_cast<int>(p)]; }
};

// Adds the time of its own lifetime to one pass of a profile.
class PassTimer {
 public:
  PassTimer(StepProfile& profile, Pass pass)
      : slot_(profile[pass]), start_(std::chrono::steady_clock::now()) {}
  ~PassTimer() {
    slot_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

 private:
  double& slot_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace sph::solver
