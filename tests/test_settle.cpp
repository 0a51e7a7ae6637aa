// The scene's `settle` (run::Simulation::settle): the starting fluid steps for that long with
// nothing joining it, then the clock starts again at 0 from the settled state. A run resumed from
// its cache does not settle again (tests/test_cache_resume.cpp); K processes settle as one
// (tests/test_mpi.cpp).
#include <gtest/gtest.h>

#include <unordered_map>

#include "io/scene/SceneLoader.h"
#include "sim/run/Simulation.h"

namespace sph {
namespace {

// A falling column (640 particles) and a nozzle over the empty end of its tank, open from t = 0.
scene::Scene damAndNozzle(std::vector<std::string> set = {}) {
  return io::scene::parseScene(R"({
  "solver": {"spacing": 0.02, "end_time": 1},
  "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.16, 0.32, 0.1]}],
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.6, 0.4, 0.1]}],
  "emitters": [{"position": [0.5, 0.3, 0.05], "direction": [0, -1, 0], "radius": 0.03,
                "speed": 1}]
})",
                               "dam_pour.json", set);
}

std::unordered_map<std::uint32_t, Vec3> positionsById(const Particles& p) {
  std::unordered_map<std::uint32_t, Vec3> at;
  for (std::size_t i = 0; i < p.size(); ++i) at[p.id[i]] = p.position(i);
  return at;
}

TEST(Settle, StartsTheClockAgainFromTheSettledFluid) {
  run::Simulation settled(damAndNozzle());
  const std::size_t start = settled.fluid().size();
  ASSERT_TRUE(settled.settle(0.1));
  EXPECT_EQ(settled.time(), 0.0);
  EXPECT_EQ(settled.stepCount(), 0u);
  EXPECT_EQ(settled.profile().steps, 0u);
  EXPECT_EQ(settled.fluid().size(), start);  // the nozzle, open from t = 0, released nothing

  // The same 0.1 s stepped plainly with the nozzle opening only later: the same particles, bit
  // for bit (the nozzle's speed sets the automatic speed of sound, so it stays in the scene).
  run::Simulation plain(damAndNozzle({"emitters[0].start=5"}));
  plain.advanceTo(0.1);
  ASSERT_EQ(plain.fluid().size(), start);
  const auto expected = positionsById(plain.fluid());
  const auto read = positionsById(settled.fluid());
  for (std::size_t i = 0; i < settled.fluid().size(); ++i) {
    const std::uint32_t id = settled.fluid().id[i];
    ASSERT_EQ(read.at(id), expected.at(id)) << "particle " << id;
  }
  // The column was falling: the settled state is not the lattice.
  const auto lattice = positionsById(run::Simulation(damAndNozzle()).fluid());
  std::size_t changed = 0;
  for (const auto& [id, x] : read) changed += (x - lattice.at(id)).norm() > 1e-3f ? 1 : 0;
  EXPECT_GT(changed, start / 2);

  // From t = 0 the nozzle pours, its particles numbered after the settled ones.
  settled.advanceTo(0.05);
  EXPECT_GT(settled.fluid().size(), start);
  for (std::size_t i = 0; i < settled.fluid().size(); ++i) {
    if (!lattice.count(settled.fluid().id[i])) {
      EXPECT_GE(settled.fluid().id[i], start);
    }
  }
}

TEST(Settle, AStopRequestLeavesTheClockRunning) {
  run::Simulation sim(damAndNozzle());
  int steps = 0;
  EXPECT_FALSE(sim.settle(
      0.1, [&](const run::Simulation&) { ++steps; }, [&] { return steps == 3; }));
  EXPECT_EQ(sim.stepCount(), 3u);
  EXPECT_GT(sim.time(), 0.0);
  EXPECT_FALSE(sim.settling());
}

}  // namespace
}  // namespace sph
