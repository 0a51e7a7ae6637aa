// Runs every variant of a sweep (bench/sweep/Sweep.h) and records what happened: wall time, steps,
// particles, the blow-up if the guard stopped it, and the metrics' values. One variant at a time,
// in this process, at the sweep's thread count; the wall time counts the steps only (not the
// setup, which is reported apart, nor the metrics' own sampling).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bench/sweep/Sweep.h"
#include "sim/scene/EnumNames.h"
#include "sim/solver/StepProfile.h"

namespace sph::sweep {

enum class RunStatus {
  Stable,   // reached the end time (or max_steps) with a finite state inside the domain
  Guard,    // the stability guard stopped it (StabilityError)
  Timeout,  // exceeded the sweep's max_wall_s
  Failed,   // another error (out of memory, a collision pass that cannot start)
};

// The status column of the sweep's CSV and report (sim/scene/EnumNames.h).
constexpr const char* nameOf(RunStatus status) {
  switch (status) {
    case RunStatus::Stable:
      return "stable";
    case RunStatus::Guard:
      return "guard";
    case RunStatus::Timeout:
      return "timeout";
    case RunStatus::Failed:
      return "failed";
  }
  return nullptr;
}

struct VariantResult {
  SweepVariant variant;
  RunStatus status = RunStatus::Stable;
  std::string message;           // the guard's or the error's message
  std::uint64_t guardStep = 0;   // Guard: the step that produced the bad state
  double guardTime = 0;          // Guard: s
  std::size_t particles = 0;     // fluid particles at the start
  std::size_t particlesEnd = 0;  // and at the end (emitters add)
  std::size_t boundaryParticles = 0;
  std::uint64_t steps = 0;
  double simTime = 0;           // s simulated
  double setupSeconds = 0;      // building the Simulation (boundary sampling, lattice)
  double wallSeconds = 0;       // stepping, the fastest of the repeats
  double cpuSeconds = 0;        // process CPU time of the same steps (all threads): on a
                                // shared machine a 1-thread run's CPU time is what its wall
                                // time would be on an idle one
  double speedOfSound = 0;      // m/s, resolved
  double stiffness = 0;         // Pa (tait) or m^2/s^2 (linear), resolved
  double h = 0;                 // m
  double maxSpeed = 0;          // m/s, largest fluid speed seen at any step
  double speedBound = 0;        // m/s, the energy bound of the scene (SceneSetup.h)
  double rssMb = 0;             // resident memory with the simulation alive, at its end
  solver::StepProfile profile;  // per-pass time of the reported run
  std::vector<double> metrics;  // one per metric column (NaN = none)

  double msPerStep() const { return steps ? 1e3 * wallSeconds / steps : 0; }
};

struct SweepResult {
  SweepSpec spec;
  int threads = 0;
  std::vector<std::string> metricColumns;
  std::vector<VariantResult> rows;
};

struct SweepRunOptions {
  std::string outputDir;  // per-variant series files go here
  int threads = -1;       // -1 = the sweep's
  std::string only;       // run only variants whose label contains this ("" = all)
  // Called after each variant (for progress lines), with the sweep's metric column names.
  std::function<void(const VariantResult&, const std::vector<std::string>& metricColumns,
                     std::size_t index, std::size_t count)>
      onVariant;
};

// Validates every variant's scene and every metric first (InputError), then runs them.
SweepResult runSweep(const SweepSpec& spec, const SweepRunOptions& options);

}  // namespace sph::sweep
