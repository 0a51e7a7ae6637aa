// The scenes every figure of bench_collision comes from: the shipped rain scenes at a chosen
// particle count, run as the paper's particle system until the rain has hit the sphere (a
// snapshot, computed with `exact`) - timings restore it, recall measures on its positions.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sim/Particles.h"
#include "sim/scene/Scene.h"
#include "sim/run/Simulation.h"

namespace sph::collisionbench {

// The shipped rain scene of density type A (dense, 12 mm lattice) or B (sparse, 24 mm) holding n
// particles: 2,500 per layer, as many layers as needed above y = 0.75 m.
scene::Scene rainScene(char density, std::size_t n, std::vector<std::string> overrides = {});

struct Snapshot {
  char density;
  std::size_t n;
  scene::Scene scene;
  run::RunState state;
  Particles particles;
};

// The scene run with `exact` (the paper's response, as in the scene) until `warm` seconds.
Snapshot takeSnapshot(char density, std::size_t n, double warm);

}  // namespace sph::collisionbench
