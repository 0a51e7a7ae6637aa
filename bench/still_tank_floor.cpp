// The still tank's floor read as a pressure sensor (docs/benchmarks.md, "Bottom pressure of
// DFSPH"), for a tank of any width: how much of DFSPH's floor error is its walls' (a ring along
// them carries more than its share, so the centre reads low by an amount that shrinks as the
// tank widens). The sensor is the tests' (tests/StillTankFloor.h).
//
//   still_tank_floor WIDTH [SOLVER [FROM END [KEY=VALUE...]]]   (read over FROM-END s)
//   e.g. still_tank_floor 0.4 dfsph 0.3 0.9 solver.wall_pressure=none
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "io/scene/SceneLoader.h"
#include "sim/run/Simulation.h"
#include "tests/StillTankFloor.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc == 4) {
    std::fprintf(stderr, "usage: %s WIDTH [wcsph|dfsph [FROM END [KEY=VALUE...]]]  (m, s)\n",
                 argv[0]);
    return 2;
  }
  const double width = std::atof(argv[1]);
  const std::string solver = argc > 2 ? argv[2] : "dfsph";
  const double from = argc > 4 ? std::atof(argv[3]) : 0.3;
  const double end = argc > 4 ? std::atof(argv[4]) : 0.9;
  if (!(width > 0.04) || !(from >= 0) || !(end > from) ||
      (solver != "wcsph" && solver != "dfsph")) {
    std::fprintf(stderr, "%s: WIDTH must be > 0.04 m, SOLVER wcsph or dfsph, END > FROM >= 0\n",
                 argv[0]);
    return 2;
  }
  const std::string w = std::to_string(width);
  std::vector<std::string> set = {"fluids[0].max=[" + w + ",0.3," + w + "]",
                                  "boundaries[0].max=[" + w + ",0.4," + w + "]",
                                  "solver.pressure=" + solver};
  for (int a = 5; a < argc; ++a) set.emplace_back(argv[a]);
  sph::scene::Scene scene;
  try {
    scene = sph::io::scene::loadScene(SPHSPLAT_SOURCE_DIR "/scenes/still_tank.json", set);
  } catch (const std::exception& e) {  // a bad KEY=VALUE: the loader's one line
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 2;
  }
  sph::run::Simulation sim(scene);
  if (scene.settle > 0) sim.settle(scene.settle);  // the scene key settle=S: FROM counts after it
  const double dx = scene.solver.spacing, rho0 = scene.solver.restDensity;
  // The depth of the water at rest density: its volume over the floor.
  const double depth = static_cast<double>(sim.fluid().size()) * dx * dx * dx / (width * width);
  const double expected = rho0 * scene.solver.gravity.norm() * depth;
  sim.advanceTo(from);
  sph::test::StillTankFloor floor(width, dx);
  const auto before = sim.solveStats();
  floor.advanceTo(sim, end);
  const auto after = sim.solveStats();
  std::printf("%s, tank %.3g m square, %zu particles, depth %.4f m, read %g-%g s:\n  ",
              solver.c_str(), width, sim.fluid().size(), depth, from, end);
  floor.print(solver.c_str(), expected, true);
  if (after.steps > before.steps) {
    const double steps = static_cast<double>(after.steps - before.steps);
    std::printf(
        "%s iterations a step: density %.2f, divergence %.2f\n", solver.c_str(),
        static_cast<double>(after.totalDensityIterations - before.totalDensityIterations) / steps,
        static_cast<double>(after.totalDivergenceIterations - before.totalDivergenceIterations) /
            steps);
  }
  return 0;
}
