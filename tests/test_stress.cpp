// The fast subset of the stability stress tests (docs/benchmarks.md, "Stability stress tests"):
// the guard stops every blow-up at the step that produced it, so no state a frame could be
// written from is ever non-finite or outside the domain; and the cases the table lists as stable
// stay stable. Scenes are the tables' at coarser resolution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "bench/sweep/Sweep.h"
#include "bench/sweep/SweepRunner.h"
#include "io/scene/SceneLoader.h"
#include "sim/run/Observables.h"
#include "sim/run/Simulation.h"
#include "sim/StabilityError.h"
#include "sim/solver/Validate.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

// Every field a frame can hold is finite and every particle is inside the domain.
::testing::AssertionResult frameIsGood(const run::Simulation& sim) {
  const Particles& p = sim.fluid();
  const Aabb& d = sim.scene().domain;
  if (const std::size_t bad = solver::firstNonFinite(p); bad < p.size())
    return ::testing::AssertionFailure() << "particle " << p.id[bad] << " has a non-finite field";
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!d.contains(p.position(i))) {
      return ::testing::AssertionFailure()
             << "particle " << p.id[i] << " is outside the domain at " << p.position(i).transpose();
    }
  }
  return ::testing::AssertionSuccess();
}

// Runs to `end`, checking the state after every step that returned (any of them could be written
// as a frame). Returns the guard's error if it stopped the run.
std::optional<StabilityError> runChecked(run::Simulation& sim, double end) {
  try {
    while (sim.time() < end) {
      sim.step(end);
      EXPECT_TRUE(frameIsGood(sim))
          << "after step " << sim.stepCount() << ", t = " << sim.time() << " s";
      if (::testing::Test::HasFailure()) return std::nullopt;
    }
  } catch (const StabilityError& e) {
    EXPECT_EQ(e.step, sim.stepCount());  // stopped at the step that made the bad state
    return e;
  }
  return std::nullopt;
}

scene::Scene inlineScene(const std::string& json, const std::vector<std::string>& edits = {}) {
  return io::scene::parseScene(json, "stress.json", edits);
}

scene::Scene damBreak(const std::vector<std::string>& edits) {
  std::vector<std::string> all = {"solver.spacing=0.0146", "solver.end_time=0.6"};  // a / dx = 10
  all.insert(all.end(), edits.begin(), edits.end());
  return test::shippedScene("dam_break", all);
}

const char* kTank =
    R"({"solver": {"spacing": 0.01}, "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.05, 0.2, 0.05]}]})";

TEST(Guard, StopsANonFiniteStateAtTheStepThatMadeIt) {
  // A NaN and an infinite velocity (positions entering a step have always passed the guard, so
  // the step's own arithmetic is where non-finite values start).
  for (const float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    run::Simulation sim(inlineScene(kTank));
    sim.advanceTo(0.01);
    const std::uint64_t before = sim.stepCount();
    Particles& p = sim.fluid();
    std::size_t i = 0;
    while (p.id[i] != 42) ++i;
    p.vy[i] = bad;
    try {
      sim.step();
      FAIL() << "the guard let a NaN through";
    } catch (const StabilityError& e) {
      EXPECT_EQ(e.kind, StabilityError::Kind::NonFinite);
      EXPECT_EQ(e.step, before + 1);
      // The NaN may have spread to neighbours through the forces; the report names the lowest id.
      EXPECT_LE(e.particleId, 42u);
      EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos);
    }
  }
}

TEST(Guard, RemovesAndCountsAParticleLeavingTheDomain) {
  run::Simulation sim(inlineScene(kTank));
  ASSERT_EQ(sim.fluid().size(), 125u);
  ASSERT_EQ(sim.params().maxLostParticles, 1u);  // automatic: 1% of the particles
  Particles& p = sim.fluid();
  // 10 km/s up through the open top (walls would stop it: the boundaries pass puts particles
  // back where they entered a solid): out of the domain in one step.
  const std::uint32_t id = p.id[0];
  p.vy[0] = 1e4f;
  sim.step();
  EXPECT_EQ(sim.lostParticles(), 1u);
  ASSERT_EQ(sim.fluid().size(), 124u);
  for (std::size_t i = 0; i < sim.fluid().size(); ++i) EXPECT_NE(sim.fluid().id[i], id);
  EXPECT_TRUE(frameIsGood(sim));
  // A second one is past the tolerance: the run stops, naming it.
  Particles& q = sim.fluid();
  const std::uint32_t second = q.id[5];
  q.vy[5] = 1e4f;
  try {
    sim.step();
    FAIL() << "a second lost particle went unnoticed";
  } catch (const StabilityError& e) {
    EXPECT_EQ(e.kind, StabilityError::Kind::LeftDomain);
    EXPECT_EQ(e.particleId, second);
    EXPECT_NE(
        std::string(e.what()).find("2 particles lost, more than solver.max_lost_particles = 1"),
        std::string::npos)
        << e.what();
  }
}

TEST(Guard, StopsAParticleLeavingTheDomainWithNoLossTolerated) {
  run::Simulation sim(inlineScene(kTank, {"solver.max_lost_particles=0"}));
  Particles& p = sim.fluid();
  p.vy[0] = 1e4f;
  try {
    sim.step();
    FAIL() << "a particle left the domain unnoticed";
  } catch (const StabilityError& e) {
    EXPECT_EQ(e.kind, StabilityError::Kind::LeftDomain);
    EXPECT_EQ(e.particleId, p.id[0]);
    EXPECT_EQ(e.step, 1u);
  }
}

// The rows of the stress tables where the guard stopped the run (docs/benchmarks.md): it must
// stop them before any bad state, and it must stop them (if a solver change makes one of these
// stable, re-run the stress sweeps and update the table and this list).
struct BlowUp {
  const char* name;
  std::vector<std::string> edits;  // on the coarse dam break
  // At the edge of stability: whether the guard stops it depends on the machine's floating-point
  // code (cfl 1.5 stopped on the AVX-512 Xeons and ran to the end on an AVX2 AMD EPYC; cfl 2.0
  // stopped in every Release build and ran to the end in the EPYC's sanitizer build). Either is
  // fine; a bad frame is not.
  bool marginal = false;
};

class GuardStops : public ::testing::TestWithParam<BlowUp> {};

TEST_P(GuardStops, BeforeABadFrame) {
  run::Simulation sim(damBreak(GetParam().edits));
  const std::optional<StabilityError> e = runChecked(sim, sim.scene().solver.endTime);
  ASSERT_FALSE(::testing::Test::HasFailure());
  if (GetParam().marginal && !e) {
    std::printf("%s: ran to the end with every frame good\n", GetParam().name);
    return;
  }
  ASSERT_TRUE(e.has_value()) << GetParam().name << " ran to the end: update docs/benchmarks.md";
  std::printf("%s: guard stopped it at step %llu, t = %.4g s\n", GetParam().name,
              static_cast<unsigned long long>(e->step), e->time);
}

INSTANTIATE_TEST_SUITE_P(
    StressTables, GuardStops,
    ::testing::Values(BlowUp{"cfl 1.5", {"solver.max_time_step=0.01", "solver.cfl=1.5"}, true},
                      BlowUp{"cfl 2.0", {"solver.max_time_step=0.01", "solver.cfl=2.0"}, true},
                      BlowUp{"cfl 3.0", {"solver.max_time_step=0.01", "solver.cfl=3.0"}},
                      // With the default tolerance it now runs to the end, losing a few
                      // particles (ZeroViscosityDamBreakRunsToTheEndLosingAFewParticles).
                      BlowUp{"zero viscosity",
                             {"solver.viscosity=0", "solver.max_lost_particles=0"}}),
    [](const ::testing::TestParamInfo<BlowUp>& param) {
      std::string n = param.param.name;
      for (char& c : n) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return n;
    });

TEST(Stress, OverlappingStartIsStoppedByTheGuard) {
  // Two lattices dx/2 apart: twice the rest density, 127 B of Tait pressure. In an open tank the
  // block explodes; the guard stops the first particle that leaves the domain.
  run::Simulation sim(inlineScene(R"({"solver": {"spacing": 0.01, "end_time": 1},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}, {"min": [0.005, 0, 0], "max": [0.055, 0.05, 0.05]}],
    "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.2, 0.3, 0.2]}]})"));
  ASSERT_EQ(sim.fluid().size(), 250u);
  const std::optional<StabilityError> e = runChecked(sim, 1.0);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->kind, StabilityError::Kind::LeftDomain);
  EXPECT_LT(e->time, 0.05);  // an explosion, not a slow drift
}

TEST(Stress, ZeroViscosityDamBreakRunsToTheEndLosingAFewParticles) {
  // Without viscosity the splash at a / dx = 13 leaves the open tank's domain (it stopped the
  // whole run at t = 0.474 s before lost particles were removed): now those are counted and the
  // run goes on, within the tolerance. How many leave by 0.6 s is a property of a chaotic splash,
  // not of the guard: 16 with walls of their summation pressure, 17 (at 0.599 s) with walls that
  // hold the extrapolated pressure, against an automatic tolerance of 1% (16). The run is given
  // twice that, so the test is about the guard letting a run with losses go on.
  const std::vector<std::string> edits = {"solver.spacing=0.01123", "solver.viscosity=0",
                                          "solver.end_time=0.6"};
  const std::size_t automatic =
      solver::deriveParams(test::shippedScene("dam_break", edits)).maxLostParticles;
  std::vector<std::string> tolerant = edits;
  tolerant.push_back("solver.max_lost_particles=" + std::to_string(2 * automatic));
  run::Simulation sim(test::shippedScene("dam_break", tolerant));
  const std::size_t start = sim.fluid().size();
  ASSERT_EQ(automatic, start / 100);  // the automatic tolerance is 1% of the particles
  EXPECT_FALSE(runChecked(sim, 0.6).has_value());
  EXPECT_EQ(sim.time(), 0.6);
  std::printf("lost %llu of %zu particles\n", static_cast<unsigned long long>(sim.lostParticles()),
              start);
  EXPECT_GT(sim.lostParticles(), 0u);
  EXPECT_EQ(sim.fluid().size() + sim.lostParticles(), start);
}

TEST(Stress, SoftEosAndLowCflStayStable) {
  for (const std::vector<std::string>& edits :
       {std::vector<std::string>{"solver.speed_of_sound_factor=3.1623"},  // stiffness x 0.1
        std::vector<std::string>{"solver.cfl=0.1", "solver.end_time=0.3"}}) {
    run::Simulation sim(damBreak(edits));
    EXPECT_FALSE(runChecked(sim, sim.scene().solver.endTime).has_value()) << edits[0];
    EXPECT_EQ(sim.fluid().size(), 800u);
  }
}

TEST(Stress, ASingleParticleFallsAndRestsOnTheFloor) {
  run::Simulation sim(inlineScene(R"({"solver": {"spacing": 0.01, "end_time": 2},
    "fluids": [{"min": [0.05, 0.1, 0.05], "max": [0.0601, 0.1101, 0.0601]}],
    "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.1, 0.2, 0.1]}]})"));
  ASSERT_EQ(sim.fluid().size(), 1u);
  ASSERT_FALSE(runChecked(sim, 2.0).has_value());
  const Particles& p = sim.fluid();
  // Resting in front of the floor's boundary particles: within a support radius, not in the wall.
  EXPECT_GT(p.y[0], 0.0f);
  EXPECT_LT(p.y[0], 0.02f);
  EXPECT_LT(p.velocity(0).norm(), 0.05f);
}

TEST(Stress, ATenMetreDropStaysInTheTank) {
  // 14 m/s impact into a pool; the automatic speed of sound (10x the impact speed) keeps the
  // compression near 1%. Coarse (dx 4 cm) version of the table's 2 cm run.
  run::Simulation sim(inlineScene(R"({"solver": {"spacing": 0.04, "end_time": 1.8},
    "fluids": [{"min": [0, 0, 0], "max": [0.4, 0.12, 0.4]}, {"min": [0.12, 10.1, 0.12], "max": [0.24, 10.22, 0.24]}],
    "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.4, 2.0, 0.4]}]})"));
  EXPECT_GT(sim.params().speedOfSound, 10 * 14.0f);
  ASSERT_FALSE(runChecked(sim, 1.8).has_value());
  const auto& y = sim.fluid().y;
  EXPECT_LT(*std::max_element(y.begin(), y.end()), 2.0f);  // the drop arrived, nothing flew out
  EXPECT_LT(run::densityError(sim.fluid(), 1000.0).maxDensity, 1050.0);
}

TEST(Stress, AnEmitterOverflowingASmallCupStaysStable) {
  // A 3 cm cup (0.14 l) under the pour nozzle (0.36 l/s): full after ~0.4 s, overflowing after.
  run::Simulation sim(inlineScene(R"({"solver": {"spacing": 0.01, "end_time": 1.2},
    "boundaries": [{"type": "cup", "centre": [0, 0, 0], "radius": 0.03, "height": 0.05},
                   {"type": "tank", "min": [-0.15, -0.05, -0.15], "max": [0.15, 0.2, 0.15]}],
    "emitters": [{"position": [0, 0.12, 0], "direction": [0, -1, 0], "radius": 0.012, "speed": 0.8}]})"));
  ASSERT_FALSE(runChecked(sim, 1.2).has_value());
  std::size_t outside = 0;  // particles that overflowed the cup
  for (std::size_t i = 0; i < sim.fluid().size(); ++i) {
    const Vec3 x = sim.fluid().position(i);
    outside += std::hypot(x.x(), x.z()) > 0.04f;
  }
  EXPECT_GT(sim.fluid().size(), 250u);
  EXPECT_GT(outside, 10u) << "the cup never overflowed";
}

// The 10^5-step run in docs/benchmarks.md, cut to 4500 steps (2.3 s): once the initial lattice
// has settled (viscosity takes its kinetic energy over ~1.5 s), the total energy (kinetic +
// potential + EOS elastic) and the mean density of the still tank hold still.
TEST(Stress, StillTankHoldsItsEnergyAndDensity) {
  const sweep::SweepSpec spec =
      sweep::parseSweep(R"({"scene": ")" + test::sourcePath("scenes/still_tank.json") + R"(",
    "set": ["solver.spacing=0.02", "solver.end_time=100"], "max_steps": 4500,
    "metrics": [{"type": "energy", "every_steps": 100, "settle": 1.5}]})",
                        "still.json");
  sweep::SweepRunOptions options;
  options.outputDir = ::testing::TempDir();
  options.threads = 0;
  const sweep::SweepResult r = sweep::runSweep(spec, options);
  ASSERT_EQ(r.rows.size(), 1u);
  ASSERT_EQ(r.rows[0].status, sweep::RunStatus::Stable) << r.rows[0].message;
  EXPECT_EQ(r.rows[0].steps, 4500u);
  ASSERT_EQ(r.metricColumns, (std::vector<std::string>{"energy_drift_pct", "rho_drift_pct"}));
  const double energyDrift = r.rows[0].metrics[0], rhoDrift = r.rows[0].metrics[1];
  std::printf("still tank, 1.5 s to step 4500: energy %+.4f%%, mean density %+.4f%%\n", energyDrift,
              rhoDrift);
  // Measured: about -0.02% and +0.0005% (docs/benchmarks.md has the 10^5-step run); an energy
  // pump (such as the poly6/spiky mismatch, tests/test_energy.cpp) gains orders of magnitude more.
  EXPECT_LT(std::abs(energyDrift), 0.1);
  EXPECT_LT(std::abs(rhoDrift), 0.05);
}

}  // namespace
}  // namespace sph
