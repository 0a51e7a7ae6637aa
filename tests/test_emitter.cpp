// The nozzle: layers one spacing apart at the given speed, the disc lattice, start/stop, the
// particle cap and the pipe's end it holds at its velocity.
#include <gtest/gtest.h>

#include <set>

#include "sim/run/Emitter.h"

namespace sph {
namespace {

scene::EmitterDesc nozzle() {
  scene::EmitterDesc e;
  e.position = Vec3(0, 1, 0);
  e.direction = Vec3(0, -1, 0);
  e.radius = 0.02f;
  e.speed = 2.0f;
  e.start = 0.1;
  e.stop = 0.6;
  return e;
}

TEST(Emitter, DiscHoldsTheLatticePointsWithinItsRadius) {
  run::Emitter e(nozzle(), 0.01f, 0.02f);
  // Points (i, k) * 0.01 with i^2 + k^2 <= 4: 13 of them.
  EXPECT_EQ(e.layer().size(), 13u);
  for (const Vec3& o : e.layer()) {
    EXPECT_LE(o.norm(), 0.02f + 1e-6f);
    EXPECT_NEAR(o.y(), 0.0f, 1e-7f);  // perpendicular to the direction
  }
}

TEST(Emitter, ReleasesSpeedOverSpacingLayersPerSecondBetweenStartAndStop) {
  run::Emitter e(nozzle(), 0.01f, 0.02f);
  Particles fluid;
  std::uint32_t nextId = 0;
  const double dt = 1e-3;
  for (int s = 1; s <= 1000; ++s) e.emit(s * dt, dt, fluid, nextId, 1000.0f);
  // 0.5 s of emission at 2 m/s with layers 0.01 m apart: 100 layers (+1 released at start).
  EXPECT_NEAR(static_cast<double>(fluid.size()) / 13.0, 101.0, 1.0);
  std::set<std::uint32_t> ids(fluid.id.begin(), fluid.id.end());
  EXPECT_EQ(ids.size(), fluid.size());
  EXPECT_EQ(nextId, fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    EXPECT_EQ(fluid.velocity(i), Vec3(0, -2, 0));
    EXPECT_LE(fluid.y[i], 1.0f + 1e-6f);
  }
}

TEST(Emitter, StopsAtItsParticleCap) {
  scene::EmitterDesc d = nozzle();
  d.maxParticles = 13 * 5;
  run::Emitter e(d, 0.01f, 0.02f);
  Particles fluid;
  std::uint32_t nextId = 0;
  for (int s = 1; s <= 1000; ++s) e.emit(s * 1e-3, 1e-3, fluid, nextId, 1000.0f);
  EXPECT_EQ(fluid.size(), 13u * 5u);
}

// Particles at the nozzle (0, 1, 0) pouring down at 2 m/s, the disc 0.02 m, spacing 0.01 m, the
// support 0.02 m: the pipe's end is the cylinder of radius 0.025 m from y = 1.01 down to 0.98.
TEST(Emitter, HoldsThePipesEndAtTheNozzlesVelocityWhilePouring) {
  run::Emitter e(nozzle(), 0.01f, 0.02f);
  Particles fluid;
  const Vec3 kick(0.3f, 0.5f, -0.2f);
  const std::vector<Vec3> inside = {
      {0, 1, 0}, {0.024f, 0.99f, 0}, {0, 1.009f, 0}, {0, 0.981f, 0.01f}};
  const std::vector<Vec3> outside = {{0.026f, 0.99f, 0}, {0, 1.011f, 0}, {0, 0.979f, 0}};
  std::uint32_t id = 0;
  for (const Vec3& x : inside) fluid.append(x, kick, id++, 1000.0f);
  for (const Vec3& x : outside) fluid.append(x, kick, id++, 1000.0f);
  for (std::size_t i = 0; i < fluid.size(); ++i) fluid.ax[i] = 1, fluid.ay[i] = -9.81f;

  Particles before = fluid;
  e.guide(0.05, 0.001, before);  // not pouring yet (start 0.1 s): nothing held
  for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(before.velocity(i), kick);

  e.guide(0.2, 0.001, fluid);
  for (std::size_t i = 0; i < inside.size(); ++i) {
    EXPECT_EQ(fluid.velocity(i), Vec3(0, -2, 0)) << "particle " << i;
    EXPECT_EQ(fluid.ay[i], 0.0f) << "particle " << i;
  }
  for (std::size_t i = inside.size(); i < fluid.size(); ++i) {
    EXPECT_EQ(fluid.velocity(i), kick) << "particle " << i;
    EXPECT_EQ(fluid.ay[i], -9.81f) << "particle " << i;
  }
  Particles after = fluid;
  for (std::size_t i = 0; i < after.size(); ++i) after.setVelocity(i, kick);
  e.guide(0.7, 0.001, after);  // stopped at 0.6 s
  for (std::size_t i = 0; i < after.size(); ++i) EXPECT_EQ(after.velocity(i), kick);
}

}  // namespace
}  // namespace sph
