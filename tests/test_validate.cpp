// The solver's invariant checks (sim/solver/Validate.h, NeighbourGrid::checkSorted): they hold on real
// states, and each catches the corruption it is there for. (SPH_VALIDATE builds run them inside
// every step; these tests run them in every build.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "sim/Assert.h"
#include "sim/grid/NeighbourGrid.h"
#include "sim/Parallel.h"
#include "sim/run/Simulation.h"
#include "sim/solver/Validate.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

struct Cloud {
  std::vector<float> x, y, z;
  std::vector<std::uint32_t> order;
  grid::NeighbourGrid grid;
  std::string check() { return grid.checkSorted(x.data(), y.data(), z.data(), x.size(), order); }
};

Cloud randomCloud() {
  Cloud c;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.3f, 0.5f);
  for (int i = 0; i < 2000; ++i)
    c.x.push_back(u(rng)), c.y.push_back(u(rng)), c.z.push_back(u(rng));
  c.grid.build(c.x.data(), c.y.data(), c.z.data(), c.x.size(), 0.05f, c.order);
  return c;
}

TEST(CheckSorted, HoldsAfterBuildAndCatchesABrokenOrder) {
  Cloud c = randomCloud();
  EXPECT_EQ(c.check(), "");
  // Two points of different cells swapped: each now sits in the other's cell.
  std::size_t a = 0, b = c.order.size() - 1;
  std::swap(c.order[a], c.order[b]);
  EXPECT_NE(c.check().find("not its own"), std::string::npos) << c.check();
  std::swap(c.order[a], c.order[b]);
  // A point listed twice (and another lost).
  const std::uint32_t keep = c.order[1];
  c.order[1] = c.order[0];
  EXPECT_NE(c.check().find("another slot holds too"), std::string::npos) << c.check();
  c.order[1] = keep;
  // Two points of one cell out of their original order: the sort must be stable.
  for (std::size_t s = 1; s < c.order.size(); ++s) {
    const grid::CellCoord p =
        c.grid.cellOf(c.x[c.order[s - 1]], c.y[c.order[s - 1]], c.z[c.order[s - 1]]);
    const grid::CellCoord q = c.grid.cellOf(c.x[c.order[s]], c.y[c.order[s]], c.z[c.order[s]]);
    if (p != q) continue;
    std::swap(c.order[s - 1], c.order[s]);
    EXPECT_NE(c.check().find("swapped order"), std::string::npos) << c.check();
    return;
  }
  FAIL() << "no cell with two points";
}

TEST(CheckSorted, HoldsForAGridThatGrewItsCells) {
  Cloud c;
  for (int i = 0; i < 50; ++i)
    c.x.push_back(1000.0f * i), c.y.push_back(0.0f), c.z.push_back(-3.0f * i);
  c.grid.build(c.x.data(), c.y.data(), c.z.data(), c.x.size(), 0.01f, c.order, 64);
  EXPECT_EQ(c.check(), "");
}

TEST(CheckState, HoldsThroughARunAndCatchesWhatTheGuardDoesNotSee) {
  setThreadCount(1);  // a unit suite: it must not compete with others for the cores
  run::Simulation sim(test::shippedScene("pour", {"solver.spacing=0.008"}));
  sim.advanceTo(0.1);
  Particles p = sim.fluid();
  const std::uint32_t next = sim.runState().nextId;
  ASSERT_GT(p.size(), 10u);
  EXPECT_EQ(solver::checkState(p, next), "");
  EXPECT_EQ(solver::firstNonFinite(p), p.size());
  // The guard checks positions and velocities only.
  p.p[3] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(solver::firstNonFinite(p), 3u);
  EXPECT_NE(solver::checkState(p, next).find("non-finite"), std::string::npos)
      << solver::checkState(p, next);
  p.p[3] = 0;
  p.az[5] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(solver::firstNonFinite(p), 5u);
  p.az[5] = 0;
  p.id[4] = p.id[2];
  EXPECT_NE(solver::checkState(p, next).find("two particles have id"), std::string::npos);
  p.id[4] = next;
  EXPECT_NE(solver::checkState(p, next).find("not handed out"), std::string::npos);
  p.id[4] = sim.fluid().id[4];
  p.collideTime.pop_back();
  EXPECT_NE(solver::checkState(p, next).find("values for"), std::string::npos);
}

TEST(CheckDensity, HoldsAfterTheDensityPassAndCatchesAMissingSelfTerm) {
  setThreadCount(1);
  for (const char* kernel : {"spiky", "poly6"}) {
    run::Simulation sim(test::shippedScene(
        "dam_break", {"solver.spacing=0.0146", std::string("solver.density_kernel=") + kernel}));
    sim.step();
    Particles p = sim.fluid();
    const scene::DensityKernel k = sim.scene().solver.densityKernel;
    EXPECT_EQ(checkDensity(p, sim.params(), k), "") << kernel;
    // A lone particle reads exactly its own term, which the check allows.
    float self = 0;
    withDensityShape(k, sim.params().kernels, [&](auto shape, float factor) {
      self = factor * sim.params().mass * sim.params().densityNormalisation * shape(0.0f);
    });
    p.rho[7] = self;
    EXPECT_EQ(checkDensity(p, sim.params(), k), "") << kernel;
    p.rho[7] = 0.9f * self;
    EXPECT_NE(checkDensity(p, sim.params(), k).find("less than its own contribution"),
              std::string::npos)
        << kernel;
    p.rho[7] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(checkDensity(p, sim.params(), k), "") << kernel;
  }
}

// In SPH_VALIDATE builds (the sanitize preset) a failed check stops the process with one line; in
// the others the check is not even evaluated.
TEST(Validate, StopsTheProcessWhenOnAndCostsNothingWhenOff) {
  bool evaluated = false;
  auto failing = [&] {
    evaluated = true;
    return std::string("a broken invariant");
  };
  if constexpr (SPH_VALIDATE != 0) {
    EXPECT_DEATH(validate("a test", failing),
                 "internal error: validation failed after a test: a broken invariant");
  } else {
    validate("a test", failing);
    EXPECT_FALSE(evaluated);
  }
}

}  // namespace
}  // namespace sph
