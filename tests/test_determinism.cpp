// A run is bit-reproducible (Box2D test_determinism.c): the same scene gives the same state hash
// every time, and, since no reduction crosses threads, with any thread count.
#include <gtest/gtest.h>

#include "sim/Parallel.h"
#include "sim/Simulation.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

std::uint64_t runPour(int threads) {
  setThreadCount(threads);
  // The pour exercises the emitter, cup, plane and sorting with a changing particle count.
  Simulation sim(test::shippedScene("pour", {"solver.spacing=0.008"}));
  sim.advanceTo(0.25);
  EXPECT_GT(sim.fluid().size(), 100u);
  return test::stateHash(sim.fluid());
}

TEST(Determinism, SameSceneSameThreadsGivesBitIdenticalState) {
  const int threads = std::max(2, omp_get_num_procs());
  EXPECT_EQ(runPour(threads), runPour(threads));
}

TEST(Determinism, ThreadCountDoesNotChangeTheResult) {
  EXPECT_EQ(runPour(1), runPour(2));
}

TEST(Determinism, TheHashSeesADifference) {
  setThreadCount(2);
  Simulation a(test::shippedScene("pour", {"solver.spacing=0.008"}));
  Simulation b(test::shippedScene("pour", {"solver.spacing=0.008", "solver.cfl=0.39"}));
  a.advanceTo(0.1);
  b.advanceTo(0.1);
  EXPECT_NE(test::stateHash(a.fluid()), test::stateHash(b.fluid()));
}

}  // namespace
}  // namespace sph
