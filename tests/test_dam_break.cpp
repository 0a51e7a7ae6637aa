// The shipped dam break against Martin & Moyce (1952): surge front (largest x of the fluid from
// the left wall, over a) within 10% at every measured point with T <= 3.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/Observables.h"
#include "sim/Simulation.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

TEST(DamBreak, SurgeFrontFollowsMartinAndMoyce) {
  const std::vector<test::SurgePoint> data = test::martinMoyce();
  ASSERT_EQ(data.size(), 15u);
  const Scene scene = test::shippedScene("dam_break");
  const double a = scene.fluids[0].hi.x() - scene.fluids[0].lo.x();
  ASSERT_NEAR(a, 0.146, 1e-6);
  ASSERT_NEAR(scene.fluids[0].hi.y() - scene.fluids[0].lo.y(), 2 * a, 1e-6);  // n^2 = 2
  const double g = -scene.solver.gravity.y();
  Simulation sim(scene);
  int checked = 0;
  for (const test::SurgePoint& p : data) {
    if (p.T > 3) break;
    sim.advanceTo(p.T / std::sqrt(2 * g / a));     // T = t sqrt(2g/a)
    const double Z = surgeFront(sim.fluid()) / a;  // the wall is at x = 0
    EXPECT_NEAR(Z, p.Z, 0.10 * p.Z) << "T = " << p.T;
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

}  // namespace
}  // namespace sph
