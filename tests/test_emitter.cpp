// The nozzle: layers one spacing apart at the given speed, the disc lattice, start/stop and the
// particle cap.
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
  run::Emitter e(nozzle(), 0.01f);
  // Points (i, k) * 0.01 with i^2 + k^2 <= 4: 13 of them.
  EXPECT_EQ(e.layer().size(), 13u);
  for (const Vec3& o : e.layer()) {
    EXPECT_LE(o.norm(), 0.02f + 1e-6f);
    EXPECT_NEAR(o.y(), 0.0f, 1e-7f);  // perpendicular to the direction
  }
}

TEST(Emitter, ReleasesSpeedOverSpacingLayersPerSecondBetweenStartAndStop) {
  run::Emitter e(nozzle(), 0.01f);
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
  run::Emitter e(d, 0.01f);
  Particles fluid;
  std::uint32_t nextId = 0;
  for (int s = 1; s <= 1000; ++s) e.emit(s * 1e-3, 1e-3, fluid, nextId, 1000.0f);
  EXPECT_EQ(fluid.size(), 13u * 5u);
}

}  // namespace
}  // namespace sph
