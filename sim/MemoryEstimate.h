// How much memory a scene will need, from its description alone, before anything is allocated
// (issue 12, item 6): a run too big for the machine is refused with one line instead of growing
// until the kernel kills it. Counts follow the code that will fill the arrays (initial fluid
// lattices, boundary samplers, emitter discs); the bytes per particle are what the arrays of a
// step take, checked against the measured peak resident memory of real runs
// (tests/test_memory_estimate.cpp: within 20% at three sizes).
#pragma once

#include <string>

#include "sim/Scene.h"

namespace sph {

struct MemoryEstimate {
  // Counts in double: a scene too big for any machine must still be described.
  double fluidParticles = 0;     // at the start
  double emittedParticles = 0;   // added by nozzles until the end time (or their stop)
  double rainParticles = 0;      // rain.feed_fluid's bound (sim/SceneSetup.h, ParticleBudget)
  double boundaryParticles = 0;  // sampled walls and containers (an upper bound)
  double rainDrops = 0;          // the rain section's budget (docs/rain.md)
  double bytes = 0;              // peak, the program's own footprint included
  // The scene key that would shrink it most ("solver.spacing", "emitters[0].radius",
  // "rain.count").
  std::string largestKey = "solver.spacing";
};

// Up to the scene's solver.end_time (the run's, after --end).
MemoryEstimate estimateMemory(const Scene& scene);

}  // namespace sph
