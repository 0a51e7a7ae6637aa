// The nozzle: layers one spacing apart at the given speed, the disc lattice, start/stop, the
// particle cap and the pipe's end it holds at its velocity.
#include <gtest/gtest.h>

#include <set>
#include <vector>

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
// `guided(e)` says which of them guide() sets to the nozzle's velocity (and zero acceleration).
const std::vector<Vec3> kInside = {
    {0, 1, 0}, {0.024f, 0.99f, 0}, {0, 1.009f, 0}, {0, 0.981f, 0.01f}};
const std::vector<Vec3> kOutside = {{0.026f, 0.99f, 0}, {0, 1.011f, 0}, {0, 0.979f, 0}};

std::vector<bool> guided(const run::Emitter& e) {
  const Vec3 kick(0.3f, 0.5f, -0.2f), gravity(0.1f, -9.81f, 0.2f);
  Particles fluid;
  std::uint32_t id = 0;
  for (const auto* points : {&kInside, &kOutside})
    for (const Vec3& x : *points) fluid.append(x, kick, id++, 1000.0f);
  for (std::size_t i = 0; i < fluid.size(); ++i)
    fluid.ax[i] = gravity.x(), fluid.ay[i] = gravity.y(), fluid.az[i] = gravity.z();
  e.guide(fluid);
  std::vector<bool> held;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const Vec3 a(fluid.ax[i], fluid.ay[i], fluid.az[i]);
    if (fluid.velocity(i) == Vec3(0, -2, 0) && a == Vec3::Zero()) {
      held.push_back(true);
    } else {
      EXPECT_EQ(fluid.velocity(i), kick) << "particle " << i;
      EXPECT_EQ(a, gravity) << "particle " << i;
      held.push_back(false);
    }
  }
  return held;
}

TEST(Emitter, HoldsThePipesEndAtTheNozzlesVelocityWhilePouring) {
  run::Emitter e(nozzle(), 0.01f, 0.02f);
  Particles jet;
  std::uint32_t nextId = 0;
  const std::vector<bool> none(kInside.size() + kOutside.size(), false);
  std::vector<bool> inside = none;
  for (std::size_t i = 0; i < kInside.size(); ++i) inside[i] = true;

  EXPECT_EQ(guided(e), none);  // before any step
  e.emit(0.05, 0.001, jet, nextId, 1000.0f);
  EXPECT_EQ(guided(e), none);  // before its start (0.1 s)
  e.emit(0.2, 0.001, jet, nextId, 1000.0f);
  EXPECT_EQ(guided(e), inside);
  e.emit(0.6005, 0.001, jet, nextId, 1000.0f);  // the step that crosses its stop (0.6 s)
  EXPECT_EQ(guided(e), inside);
  e.emit(0.6015, 0.001, jet, nextId, 1000.0f);
  EXPECT_EQ(guided(e), none);
}

// A nozzle spent by its cap holds its pipe's end through the step that releases the last layer,
// and not after it.
TEST(Emitter, HoldsThePipesEndUntilTheStepAfterItsLastLayer) {
  scene::EmitterDesc d = nozzle();
  d.maxParticles = 13 * 3;
  run::Emitter e(d, 0.01f, 0.02f);
  Particles jet;
  std::uint32_t nextId = 0;
  int s = 100;
  while (jet.size() < d.maxParticles) {
    e.emit(++s * 1e-3, 1e-3, jet, nextId, 1000.0f);
    EXPECT_TRUE(guided(e)[0]) << "step " << s;
  }
  e.emit(++s * 1e-3, 1e-3, jet, nextId, 1000.0f);
  EXPECT_EQ(jet.size(), d.maxParticles);
  EXPECT_FALSE(guided(e)[0]);
}

}  // namespace
}  // namespace sph
