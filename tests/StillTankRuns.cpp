#include "tests/StillTankRuns.h"

#include <gtest/gtest.h>

#include "sim/run/Simulation.h"
#include "tests/TestSupport.h"

namespace sph::test {

scene::Scene narrowStillTank(std::vector<std::string> more) {
  more.insert(more.begin(), {"fluids[0].max=[0.12,0.3,0.12]", "boundaries[0].max=[0.12,0.4,0.12]"});
  return shippedScene("still_tank", more);
}

StillTankFloor readDfsphStillTank(const std::vector<std::string>& more, double from, double end,
                                  const char* name) {
  std::vector<std::string> set = {"solver.pressure=dfsph"};
  set.insert(set.end(), more.begin(), more.end());
  const scene::Scene scene = narrowStillTank(set);
  run::Simulation sim(scene);
  if (scene.settle > 0) sim.settle(scene.settle);  // the scene key; `from` counts after it
  sim.advanceTo(from);
  StillTankFloor floor(0.12, scene.solver.spacing);
  floor.advanceTo(sim, end);
  floor.print(name, scene.solver.restDensity * 9.81 * 0.3, true);
  return floor;
}

void expectStillTank(const StillTankFloor& floor, std::size_t fast) {
  EXPECT_EQ(floor.heaveSteps(), 0);
  EXPECT_NEAR(floor.lastTopHeight(), floor.firstTopHeight(), 0.001);
  EXPECT_LE(floor.fastParticles(), fast);
}

}  // namespace sph::test
