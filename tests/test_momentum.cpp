// With no gravity and no walls, the symmetric pressure and viscosity forces conserve total
// linear momentum to round-off (DESIGN.md, "Forces").
#include <gtest/gtest.h>

#include <random>

#include "sim/run/Observables.h"
#include "sim/run/Simulation.h"

namespace sph {
namespace {

TEST(Momentum, IsConservedOverAThousandStepsWithoutGravityOrWalls) {
  scene::Scene s;
  s.solver.spacing = 0.01f;
  s.solver.gravity = Vec3::Zero();
  s.solver.viscosity = 1e-3f;
  s.solver.speedOfSound = 20.0f;
  scene::FluidBlock b;
  b.lo = Vec3::Zero(), b.hi = Vec3(0.12f, 0.1f, 0.08f);
  s.fluids.push_back(b);
  s.domain.lo = Vec3::Constant(-5), s.domain.hi = Vec3::Constant(5);
  run::Simulation sim(s);
  // A stirred, compressed blob: random velocities and a squeeze, so every force term is busy.
  std::mt19937 rng(2);
  std::normal_distribution<float> n(0, 0.3f);
  Particles& p = sim.fluid();
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = n(rng) + 0.5f, p.vy[i] = n(rng), p.vz[i] = n(rng) - 0.2f;
    p.x[i] *= 0.97f;
  }
  const double m = sim.params().mass;
  const Vec3d before = run::momentum(p, m);
  std::vector<Vec3> initial(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) initial[p.id[i]] = p.velocity(i);
  double scale = 0;  // sum of |m v|: what round-off is relative to
  for (std::size_t i = 0; i < p.size(); ++i) scale += m * p.velocity(i).norm();
  for (int step = 0; step < 1000; ++step) sim.step();
  const Vec3d after = run::momentum(sim.fluid(), m);
  // Float accumulation over ~1000 steps: a few ulps of the largest terms per step.
  EXPECT_LT((after - before).norm(), 1e-5 * scale)
      << "before " << before.transpose() << " after " << after.transpose();
  // And the particles did interact: their velocities changed a lot, only the sum did not.
  double change = 0;
  const Particles& q = sim.fluid();
  for (std::size_t i = 0; i < q.size(); ++i) change += (q.velocity(i) - initial[q.id[i]]).norm();
  EXPECT_GT(change / q.size(), 0.05);
}

}  // namespace
}  // namespace sph
