// The shipped dam break against Martin & Moyce (1952): surge front (largest x of the fluid from
// the left wall, over a) within 10% at every measured point with T <= 3. And the gate finding of
// the dam-break study (docs/benchmarks.md, "The dam-break front: convergence, gate, walls and
// viscosity"): without viscosity the front runs well ahead of the experiment's clock, and the same
// front matches it once that clock starts 24.5 ms before the release.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "sim/run/Observables.h"
#include "sim/run/Simulation.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

TEST(DamBreak, SurgeFrontFollowsMartinAndMoyce) {
  const std::vector<test::SurgePoint> data = test::martinMoyce();
  ASSERT_EQ(data.size(), 15u);
  const scene::Scene scene = test::shippedScene("dam_break");
  const double a = scene.fluids[0].hi.x() - scene.fluids[0].lo.x();
  ASSERT_NEAR(a, 0.146, 1e-6);
  ASSERT_NEAR(scene.fluids[0].hi.y() - scene.fluids[0].lo.y(), 2 * a, 1e-6);  // n^2 = 2
  const double g = -scene.solver.gravity.y();
  run::Simulation sim(scene);
  int checked = 0;
  for (const test::SurgePoint& p : data) {
    if (p.T > 3) break;
    sim.advanceTo(p.T / std::sqrt(2 * g / a));          // T = t sqrt(2g/a)
    const double Z = run::surgeFront(sim.fluid()) / a;  // the wall is at x = 0
    EXPECT_NEAR(Z, p.Z, 0.10 * p.Z) << "T = " << p.T;
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

TEST(DamBreak, InviscidFrontMatchesMartinAndMoyceWithTheGateDelay) {
  // DFSPH without viscosity at a / dx = 15 (2,700 particles; the lattice fills the tank's depth).
  const scene::Scene scene = test::shippedScene(
      "dam_break", {"quality=accurate", "solver.viscosity=0", "solver.spacing=0.0097333"});
  const double a = 0.146, g = -scene.solver.gravity.y();
  std::vector<std::pair<double, double>> points;  // (simulated time, Z measured there)
  for (const test::SurgePoint& p : test::martinMoyce()) {
    if (p.T > 3) break;
    points.push_back({p.T / std::sqrt(2 * g / a), p.Z});
  }
  ASSERT_EQ(points.size(), 4u);
  // The front at each point's time and at every 0.5 ms before it, to 30 ms: the experiment's
  // clock started at the release of a gate that took time to clear the water.
  constexpr int kOffsets = 61;
  constexpr double kOffsetStep = 0.5e-3;  // s
  std::vector<double> stops;
  for (const auto& [t, Z] : points) {
    for (int k = 0; k < kOffsets; ++k) stops.push_back(t - k * kOffsetStep);
  }
  std::sort(stops.begin(), stops.end());
  run::Simulation sim(scene);
  std::vector<double> fronts;
  for (double t : stops) {
    sim.advanceTo(t);
    fronts.push_back(run::surgeFront(sim.fluid()) / a);
  }
  auto frontAt = [&](double t) {
    return fronts[std::lower_bound(stops.begin(), stops.end(), t - 1e-12) - stops.begin()];
  };
  for (const auto& [t, Z] : points)
    EXPECT_GT(frontAt(t), 1.08 * Z) << "t = " << t;  // from the release: 9-17% ahead
  // The gate that fits best, and how well. The sweep bench/sweeps/dam_break_wall_pressure.json
  // measures both at a / dx = 10-30: the fitted gate converges to ~24 ms and its RMS falls
  // (4.2% to 2.1% with the walls that hold pressure; 1.6% to 0.8% with walls that hold none,
  // whose bottom layer, pushing with twice the hydrostatic pressure, runs out faster at first).
  double bestRms = 1e9, bestOffset = 0;
  for (int k = 0; k < kOffsets; ++k) {
    double sum = 0;
    for (const auto& [t, Z] : points) {
      const double e = frontAt(t - k * kOffsetStep) / Z - 1;
      sum += e * e;
    }
    const double rms = std::sqrt(sum / points.size());
    if (rms < bestRms) bestRms = rms, bestOffset = k * kOffsetStep;
  }
  std::printf("inviscid front: best gate %.1f ms, RMS %.2f%%\n", 1e3 * bestOffset, 100 * bestRms);
  EXPECT_GT(bestOffset, 0.015);
  EXPECT_LT(bestOffset, 0.030);
  EXPECT_LT(bestRms, 0.04);  // measured: 3.1% (the plain DFSPH: 3.4%; walls that hold none: 1.4%)
}

}  // namespace
}  // namespace sph
