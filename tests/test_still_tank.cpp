// Hydrostatic validation (DESIGN.md): water at rest in the shipped still tank (narrowed to a few
// thousand particles) must carry the pressure rho0 g depth at the bottom (within 1%), read in the
// bottom layer's p and by a sensor in the floor (tests/StillTankFloor.h, the same reading as
// DFSPH's in test_dfsph.cpp), stay within 1% of the rest density and lose no particle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sim/run/Observables.h"
#include "sim/run/Simulation.h"
#include "tests/StillTankFloor.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

TEST(StillTank, HydrostaticPressureAndDensityAfterSettling) {
#if defined(__SANITIZE_ADDRESS__)
  // Its 3 s of settling take more than the suite's 15-minute limit under the sanitizers; the
  // steps it runs are the dam break's and the stress tests', which run here.
  GTEST_SKIP() << "3 s of settling take over 15 minutes under AddressSanitizer";
#endif
  const scene::Scene scene = test::shippedScene(
      "still_tank", {"fluids[0].max=[0.12,0.3,0.12]", "boundaries[0].max=[0.12,0.4,0.12]"});
  run::Simulation sim(scene);
  const std::size_t count = sim.fluid().size();
  ASSERT_EQ(count, 12u * 30u * 12u);
  const double dx = scene.solver.spacing, rho0 = scene.solver.restDensity, g = 9.81;
  // Depth from the free surface of the water at rest density: the tank's cross-section holds
  // `count` cells of spacing^3.
  const double surface = count * dx * dx * dx / (0.12 * 0.12);

  // Settle: the initial lattice is unloaded and falls into place, and the water along the walls
  // takes seconds to find its rest; the walls' correction toward the extrapolated pressure
  // (sim/solver/WcsphWalls.cpp) follows it with a lag of 50 h / c. From 2.25 s on it is the rest
  // state.
  sim.advanceTo(2.25);
  // WCSPH pressure is noisy step to step: the bottom layer is averaged over every step, the
  // density over 15 frames. The walls hold the pressure the water extrapolates to them, so the
  // bottom layer reads -0.21% in the native build (AVX-512), -0.81% for x86-64-v2 and +0.10% for
  // x86-64-v3, the floor sensor -0.01%, +0.51% and -0.34%; with walls of their own summation
  // pressure the bottom layer read -0.82%, -1.44% (this test failed) and -0.55%.
  double densityDeviation = 0;
  int frames = 0;
  test::StillTankFloor floor(0.12, dx);
  for (double t = 2.3; t <= 3.0 + 1e-9; t += 0.05, ++frames) {
    floor.advanceTo(sim, t);
    const Particles& p = sim.fluid();
    ASSERT_GT(run::bottomLayer(p, dx).count, 100u);
    densityDeviation += run::densityError(p, rho0).meanDeviation;
  }
  densityDeviation /= frames;
  const double pressure = floor.bottomLayerPressure();
  const double expected = rho0 * g * (surface - floor.bottomLayerHeight());
  std::printf(
      "bottom layer: %.1f Pa, rho0 g depth %.1f Pa (%+.2f%%); mean |rho - rho0| / rho0 %.3f%%\n",
      pressure, expected, 100 * (pressure - expected) / expected, 100 * densityDeviation);
  EXPECT_NEAR(pressure, expected, 0.01 * expected) << "bottom pressure " << pressure << " Pa";
  EXPECT_LT(densityDeviation, 0.01);
  // The floor's sensor (the middle 6 x 6 cm; every step from 2.25 s): the depth of the floor is
  // the surface's height.
  const double floorExpected = rho0 * g * surface;
  floor.print("wcsph", floorExpected, true);
  EXPECT_NEAR(floor.centrePressure(), floorExpected, 0.01 * floorExpected);
  // At rest the walls hold the water's weight: p and the walls' pressure are what the solver
  // applied.
  EXPECT_NEAR(floor.loadOverWeight(), 1.0, 0.005);
  // Beside the walls p is the weight of the water above, as in the middle (StillTankFloor.h):
  // the floor's layer along the walls and the water within 1.5 spacings of a side wall read
  // -0.18% and +0.75% (native build; the floor's layer in the middle -0.45%).
  EXPECT_NEAR(floor.pressureError(test::StillTankFloor::kFloorLayerRim), 0.0, 0.03);
  EXPECT_NEAR(floor.pressureError(test::StillTankFloor::kBesideSideWalls), 0.0, 0.03);

  const Particles& p = sim.fluid();
  ASSERT_EQ(p.size(), count);  // none lost
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_TRUE(p.x[i] >= 0 && p.x[i] <= 0.12f && p.z[i] >= 0 && p.z[i] <= 0.12f && p.y[i] >= 0 &&
                p.y[i] <= 0.4f)
        << "particle " << p.id[i] << " escaped to " << p.position(i).transpose();
  }
  // And it is still: settled speeds are tiny compared with sqrt(g depth) ~ 1.7 m/s.
  EXPECT_LT(run::maxSpeed(p), 0.1f);
}

}  // namespace
}  // namespace sph
