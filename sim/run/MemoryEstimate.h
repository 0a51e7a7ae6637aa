// How much memory a scene will need, from its description alone, before anything is allocated:
// a run too big for the machine is refused with one line instead of growing until the kernel
// kills it. Counts follow the code that will fill the arrays (initial fluid lattices, boundary
// samplers, emitter discs); the bytes per particle are what the arrays of a step take, checked
// against the measured peak resident memory of real runs (tests/test_memory_estimate.cpp: within
// 20% at three sizes).
#pragma once

#include <string>

#include "sim/scene/Scene.h"

namespace sph::run {

struct MemoryEstimate {
  // Counts in double: a scene too big for any machine must still be described.
  double fluidParticles = 0;     // at the start
  double emittedParticles = 0;   // added by nozzles until the end time (or their stop)
  double rainParticles = 0;      // rain.feed_fluid's bound (sim/solver/SceneSetup.h, ParticleBudget)
  double boundaryParticles = 0;  // sampled walls and containers (an upper bound)
  double rainDrops = 0;          // the rain section's budget (docs/rain.md)
  double bytes = 0;              // peak, the program's own footprint included
  // The scene key that would shrink it most ("solver.spacing", "emitters[0].radius",
  // "rain.count").
  std::string largestKey = "solver.spacing";
  // On K processes (mpirun -np K) `bytes` is rank 0's, the largest: see RankShare. Of it,
  // `rootOnlyBytes` is what rank 0 alone holds (the gathered frames, the rain's drops and, when
  // the frames are written together, the water cells they meet).
  int ranks = 1;
  double rootOnlyBytes = 0;
};

// How a run on K processes (docs/scaling.md) shares the scene (`distributed`: a run under mpirun,
// K = 1 included). Each rank holds its slab of the fluid - a 1/K share, 10% more for the imbalance
// the re-cut allows (max/mean 1.03 measured on the dam break, docs/notes/2026-11-25-scale-mpi.md)
// and a plane of ghosts of the support radius at each of its two faces - but all of the boundary
// particles; rank 0 holds every fluid particle once more when the frames are gathered to it
// (`gathersFrames`: no parallel HDF5).
struct RankShare {
  int ranks = 1;
  bool distributed = false;
  bool gathersFrames = false;
};

// Up to the scene's solver.end_time (the run's, after --end); one rank's under `share`.
MemoryEstimate estimateMemory(const scene::Scene& scene, const RankShare& share = {});

}  // namespace sph::run
