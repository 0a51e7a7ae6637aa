// DFSPH's two viscosity forms (solver.viscosity_form, sim/solver/DfsphViscosity.cpp): Müller's
// Laplacian damps every relative motion of a pair, Monaghan's only its approach along the line
// between them; and what that buys a still tank.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sim/InputError.h"
#include "sim/run/Simulation.h"
#include "tests/StillTankRuns.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

// The largest acceleration of one DFSPH step of a free block (no gravity, no walls) turning as a
// rigid body about its vertical axis at 2 rad/s. Such a motion neither compresses the block nor
// moves one particle toward another, so the pressure solvers add only their rounding (1.5e-4
// m/s^2 at this step of 5 ms) and the rest is the viscosity's. The viscosity stays under the step
// bound of Monaghan's form (SceneSetup.cpp, timeStep()): at 0.01 m^2/s its step of 0.5 ms made
// the solvers' rounding, which grows as 1/dt^2, read 0.017 m/s^2.
float rigidTurnAcceleration(const char* form) {
  scene::Scene s = test::shippedScene(
      "still_tank",
      {"solver.pressure=dfsph", std::string("solver.viscosity_form=") + form,
       "solver.gravity=[0,0,0]", "solver.viscosity=0.0009", "fluids[0].max=[0.1,0.1,0.1]"});
  s.boundaries.clear();
  run::Simulation sim(s);
  Particles& p = sim.fluid();
  constexpr float kOmega = 2.0f, kCentre = 0.05f;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = -kOmega * (p.z[i] - kCentre), p.vy[i] = 0, p.vz[i] = kOmega * (p.x[i] - kCentre);
  }
  sim.step();
  const Particles& q = sim.fluid();
  float largest = 0;
  for (std::size_t i = 0; i < q.size(); ++i)
    largest =
        std::max(largest, std::sqrt(q.ax[i] * q.ax[i] + q.ay[i] * q.ay[i] + q.az[i] * q.az[i]));
  return largest;
}

TEST(ViscosityForm, MonaghansLeavesARigidTurnAloneWhereTheLaplacianDragsItsEdges) {
  const float laplacian = rigidTurnAcceleration("laplacian");
  const float monaghan = rigidTurnAcceleration("monaghan");
  std::printf("largest acceleration of a rigid turn: laplacian %.3g, monaghan %.3g m/s^2\n",
              laplacian, monaghan);
  // The Laplacian's sums are one-sided at the block's faces, where the turn's velocity is not
  // harmonic in the particles' discrete sense: a drag that a rigid motion should not feel.
  EXPECT_GT(laplacian, 0.05f);
  // Monaghan's form sees only v_ij . x_ij, zero for a rigid turn: what is left is rounding
  // (0.06% of the Laplacian's here).
  EXPECT_LT(monaghan, 1e-2f * laplacian);
}

TEST(ViscosityForm, IsRefusedWithWcsph) {
  try {
    test::shippedScene("still_tank", {"solver.viscosity_form=monaghan"});
    FAIL() << "a WCSPH scene took solver.viscosity_form";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("viscosity_form"), std::string::npos) << e.what();
  }
}

// The tests' still tank (0.12 m square, 0.3 m of water, 4,320 particles) over 5-10 s. With the
// Laplacian form its packing creeps at 0.7-4.4 cm/s, 0-76 particles ever over 1 cm/s, chaotically
// (tests/test_dfsph.cpp); Monaghan's form at 2.5 times the automatic viscosity read 0.24-2.35
// cm/s and 0-12 particles at five gravities, with the floor's pressure within 1.3% of the weight
// above it; at G = 9.81, 0.90-2.03 cm/s and 0-11 particles on the x86-64-v2, x86-64-v3 and
// sanitize builds. The bound is a hundredth of the particles: the Laplacian's 51 and 21 fail it.
TEST(ViscosityForm, MonaghansFormHoldsTheStillTanksCreepToAFewParticles) {
  const test::StillTankFloor floor = test::readDfsphStillTank({"solver.viscosity_form=monaghan"},
                                                              5.0, 10.0, "dfsph, monaghan, 5-10 s");
  constexpr std::size_t kParticles = 12 * 30 * 12;
  test::expectStillTank(floor, kParticles / 100);
}

// Monaghan's form is explicit and, with the spiky gradient, stiff at close range: with the
// accurate preset and 4 times the automatic viscosity (nu' = 0.011 m^2/s, about the peer's own
// 0.01) the tests' still tank blew up at 0.6 s at gravity's step of 2.9 ms (particles through the
// side walls), and held at 1.6 ms. The step now keeps to 0.03 h^2 / nu' (1.1 ms here).
TEST(ViscosityForm, MonaghansFormAtFourTimesTheViscosityKeepsAStableStep) {
  const scene::Scene s = test::narrowStillTank({"quality=accurate", "solver.viscosity=0.0045"});
  run::Simulation sim(s);
  const float h = s.solver.supportRadius();
  const float bound = 0.03f * h * h / (scene::SolverParams::kMonaghanShare * 0.0045f);
  EXPECT_LE(sim.nextTimeStep(), bound * 1.0001f);
  ASSERT_NO_THROW(sim.advanceTo(0.8));
  EXPECT_EQ(sim.lostParticles(), 0u);
  const Particles& f = sim.fluid();
  for (std::size_t i = 0; i < f.size(); ++i) {
    ASSERT_TRUE(f.x[i] > 0 && f.x[i] < 0.12f && f.z[i] > 0 && f.z[i] < 0.12f && f.y[i] > 0)
        << "particle " << f.id[i] << " left the tank";
  }
}

}  // namespace
}  // namespace sph
