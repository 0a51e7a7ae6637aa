// rain.feed_fluid (docs/rain.md, "Rain that fills the pool"): the water of the drops that land in
// the pool joins the SPH fluid, one particle per particle's worth, so the mass the fluid gains is
// the rain's that landed, the pool's level rises by that volume over its area, runs are
// deterministic, and without the key the rain leaves the fluid exactly as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "io/scene/SceneLoader.h"
#include "sim/InputError.h"
#include "sim/run/MemoryEstimate.h"
#include "sim/run/Observables.h"
#include "sim/solver/SceneSetup.h"
#include "sim/run/Simulation.h"
#include "sim/rain/RainFeed.h"
#include "sim/rain/RainSystem.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

constexpr double kSide = 0.16;        // m, the tank's inner width and depth: the pool's area
constexpr double kDropVolume = 1e-7;  // m^3: ten drops make a particle of 0.01 m
constexpr float kSpacing = 0.01f;

// A still pool 5 cm deep in a 16 x 16 cm tank, rain over all of it (spawn "region", so where it
// lands does not depend on the camera). The speed of sound is fixed so that the runs with and
// without the feed differ only in the rain's water (the feed otherwise raises it to cover the
// rain's entry speed, sim/solver/SceneSetup.cpp).
// `feedKeys` replaces the rain's feed_fluid and drop_volume keys.
std::string poolScene(bool feed, int seed = 7, std::string feedKeys = "") {
  if (feedKeys.empty())
    feedKeys =
        std::string(R"("feed_fluid": )") + (feed ? "true" : "false") + R"(, "drop_volume": 1e-7)";
  return R"({"name": "pool",
    "solver": {"spacing": 0.01, "support": 2.0, "rest_density": 1000, "cfl": 0.4,
               "end_time": 1, "speed_of_sound": 30},
    "fluids": [{"min": [0, 0, 0], "max": [0.16, 0.05, 0.16]}],
    "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.16, 0.3, 0.16]}],
    "camera": {"position": [0.5, 0.4, 0.5], "target": [0.08, 0.05, 0.08], "fov": 40},
    "rain": {"count": 1500, "fall_speed": 3, "seed": )" +
         std::to_string(seed) + R"(, "spawn": "region",
             "region": {"min": [0, 0, 0], "max": [0.16, 0.25, 0.16]},
             )" +
         feedKeys + R"(},
    "output": {"fps": 30}})";
}

bool sameFluid(const Particles& a, const Particles& b) {
  return a.size() == b.size() && test::stateHash(a) == test::stateHash(b);
}

TEST(RainFeed, ConservesMassOverManyLandings) {
  const scene::Scene scene = io::scene::parseScene(poolScene(true), "pool.json");
  run::Simulation sim(scene);
  ASSERT_NE(sim.rainFeed(), nullptr);
  const std::size_t before = sim.fluid().size();
  sim.advanceTo(0.3);
  const rain::FeedState& f = sim.runState().rain;
  // Every drop the rain counted as landing in the water, and only those, was fed.
  EXPECT_EQ(f.landedDrops, sim.rainFeed()->stepper().system().counters().hitWater);
  ASSERT_GT(f.landedDrops, 2000u);
  ASSERT_GT(f.particles, 200u);
  EXPECT_EQ(sim.lostParticles(), 0u);
  // Fluid mass after = before + landed rain - what is still pending, to round-off.
  const double particle = static_cast<double>(kSpacing) * kSpacing * kSpacing;
  const double rho0 = scene.solver.restDensity;
  const double gained = rho0 * particle * static_cast<double>(sim.fluid().size() - before);
  const double landed = rho0 * kDropVolume * static_cast<double>(f.landedDrops);
  EXPECT_NEAR(gained, landed - rho0 * f.pending, 1e-12 * landed);
  EXPECT_EQ(sim.fluid().size(), before + f.particles);
  EXPECT_GE(f.pending, 0.0);
  EXPECT_LT(f.pending, particle);
  // The new particles carry fresh ids and entered inside the tank, moving with the rain.
  EXPECT_EQ(sim.runState().nextId, before + f.particles);
  std::size_t fresh = 0;
  for (std::size_t i = 0; i < sim.fluid().size(); ++i) {
    if (sim.fluid().id[i] < before) continue;
    ++fresh;
    const Vec3 p = sim.fluid().position(i);
    EXPECT_TRUE(p.x() >= 0 && p.x() <= kSide && p.z() >= 0 && p.z() <= kSide && p.y() >= 0 &&
                p.y() < 0.25)
        << "particle " << sim.fluid().id[i] << " at " << p.transpose();
  }
  EXPECT_EQ(fresh, f.particles);
  // The particle budget (memory check, id limits) bounds what the rain made by that time: at most
  // one landing per drop per frame, 1500 x 9 x 0.1 particles.
  scene::Scene until = scene;
  until.solver.endTime = 0.3;
  EXPECT_EQ(solver::particleBudget(until).rain, 1350u);
  EXPECT_GE(solver::particleBudget(until).rain, f.particles);
  EXPECT_EQ(solver::particleBudget(until).total(), before + 1350u);
  EXPECT_EQ(run::estimateMemory(until).rainParticles, 1350.0);
  try {
    solver::requireIdsBelow(until, before + 1000, "a test", "why");
    FAIL() << "the rain's 1350 particles passed an id limit 1000 above the pool's";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pool.json: rain.drop_volume: the rain that feeds the "
                                         "fluid could make up to 1,350 particles by t = 0.3 s"),
              std::string::npos)
        << e.what();
  }
}

TEST(RainFeed, ThePoolRisesByTheLandedVolumeOverItsArea) {
  const scene::Scene fed = io::scene::parseScene(poolScene(true), "pool.json");
  const scene::Scene dry = io::scene::parseScene(poolScene(false), "pool.json");
  run::Simulation a(fed), b(dry);
  // Columns away from the walls (one support radius), searched from inside the water to above
  // anything the rain could fill in this run.
  const float h = fed.solver.supportRadius();
  Aabb columns;
  columns.lo = Vec3(h, 0.02f, h);
  columns.hi = Vec3(kSide - h, 0.2f, kSide - h);
  auto level = [&](const run::Simulation& s) {
    return run::waterLevel(s.fluid(), columns, h, kSpacing);
  };
  // Averaged over the frames of the last 0.1 s: the fresh particles still splash the surface.
  const double end = 0.5;
  double rise = 0, predicted = 0;
  int frames = 0;
  for (double t = end - 0.1; t <= end + 1e-9; t += 1.0 / 30, ++frames) {
    a.advanceTo(t), b.advanceTo(t);
    rise += level(a) - level(b);
    predicted += kDropVolume * static_cast<double>(a.runState().rain.landedDrops) / (kSide * kSide);
  }
  rise /= frames, predicted /= frames;
  // 10%: the still pool's level reads 0.15 mm below its 5 cm, but this one is stirred by ~75
  // particles a frame entering at 3 m/s (a third of its particles move faster than 0.3 m/s):
  // its spray and the particles just placed above the surface read less than half full, so the
  // rise reads low; measured -4.5% (docs/benchmarks.md, "Rain").
  std::printf("level rise %.4f m, landed volume / area %.4f m (%+.1f%%)\n", rise, predicted,
              100 * (rise - predicted) / predicted);
  ASSERT_GT(predicted, 2.0 * kSpacing);  // a rise of several particle layers
  EXPECT_NEAR(rise, predicted, 0.1 * predicted);
}

// The shipped demonstration: its pool gains particles within a few frames.
TEST(RainFeed, TheShippedSceneFillsItsPool) {
  run::Simulation sim(test::shippedScene("rain_fill"));
  const std::size_t before = sim.fluid().size();
  sim.advanceTo(0.1);
  const rain::FeedState& f = sim.runState().rain;
  EXPECT_GT(f.particles, 100u);
  EXPECT_EQ(sim.fluid().size(), before + f.particles);
  EXPECT_EQ(sim.lostParticles(), 0u);
}

TEST(RainFeed, RunsAreDeterministicAndTheSeedMatters) {
  auto run = [](int seed) {
    run::Simulation sim(io::scene::parseScene(poolScene(true, seed), "pool.json"));
    sim.advanceTo(0.15);
    return std::make_pair(sim.fluid(), sim.runState().rain.landedDrops);
  };
  const auto [a, na] = run(7);
  const auto [b, nb] = run(7);
  const auto [c, nc] = run(8);
  EXPECT_TRUE(sameFluid(a, b));
  EXPECT_EQ(na, nb);
  EXPECT_GT(na, 0u);
  EXPECT_FALSE(sameFluid(a, c));
}

TEST(RainFeed, WithoutItTheRainLeavesTheFluidAsItWas) {
  const scene::Scene dry = io::scene::parseScene(poolScene(false), "pool.json");
  scene::Scene noRain = dry;
  noRain.rain.reset();
  run::Simulation a(dry), b(noRain);
  EXPECT_EQ(a.rainFeed(), nullptr);
  a.advanceTo(0.1), b.advanceTo(0.1);
  EXPECT_TRUE(sameFluid(a.fluid(), b.fluid()));
  EXPECT_EQ(a.runState().rain.landedDrops, 0u);
  EXPECT_EQ(a.stepCount(), b.stepCount());
}

// The rain system records where drops entered the water only when it feeds the fluid: the
// first sample of the drop's path inside a water cell.
TEST(RainFeed, LandingsAreRecordedOnlyWhenFeedingAndLieInTheWater) {
  std::vector<Vec3> fluid;
  for (int i = 0; i < 20; ++i)
    for (int k = 0; k < 20; ++k)
      for (int j = 0; j < 5; ++j) fluid.emplace_back(0.01f * i, 0.01f * j, 0.01f * k);
  const rain::WaterCells water(fluid, 0.02f);
  rain::RainObstacles obstacles;
  obstacles.water = &water;
  scene::CameraDesc camera;
  camera.position = Vec3(0.5f, 0.4f, 0.5f), camera.target = Vec3(0.1f, 0.05f, 0.1f);
  for (bool feed : {false, true}) {
    scene::RainDesc d;
    d.count = 2000, d.fallSpeed = 3, d.seed = 3, d.spawn = scene::RainSpawn::Region;
    d.region.lo = Vec3(0, 0, 0), d.region.hi = Vec3(0.2f, 0.3f, 0.2f);
    d.feedFluid = feed;
    rain::RainSystem rain(d, 1.0f);
    rain.reset(camera, obstacles);
    std::uint64_t hits = 0;
    for (int frame = 0; frame < 10; ++frame) {
      const std::uint64_t before = rain.counters().hitWater;
      rain.update(camera, 1.0f / 30, obstacles);
      hits += rain.counters().hitWater - before;
      if (!feed) {
        EXPECT_TRUE(rain.landings().empty());
        continue;
      }
      ASSERT_EQ(rain.landings().size(), rain.counters().hitWater - before);
      for (const Vec3& p : rain.landings()) {
        EXPECT_TRUE(water.contains(p));
        // Within a quarter cell of the water's top cells (y < 0.06 m): where the path entered.
        EXPECT_LT(p.y(), 0.06f) << p.transpose();
        EXPECT_GT(p.y(), 0.06f - 0.1f / 30 * 3 - 0.005f) << p.transpose();
      }
    }
    EXPECT_GT(hits, 500u) << "feed " << feed;
  }
}

std::string errorOf(const std::string& feedKeys) {
  try {
    io::scene::parseScene(poolScene(true, 7, feedKeys), "r.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RainFeed, BadKeysAreRefusedWithOneLine) {
  const scene::Scene s = io::scene::parseScene(poolScene(true), "r.json");
  EXPECT_TRUE(s.rain->feedFluid);
  EXPECT_EQ(s.rain->dropVolume, 1e-7);
  // The default: a real 2 mm drop.
  EXPECT_NEAR(scene::RainDesc{}.dropVolume, M_PI / 6 * 8e-9, 1e-13);
  EXPECT_FALSE(scene::RainDesc{}.feedFluid);
  struct Bad {
    const char* keys;
    const char* expect;
  };
  for (const Bad& b : std::initializer_list<Bad>{
           {R"("feed_fluid": "yes")", "r.json: rain.feed_fluid:"},
           {R"("drop_volume": 0)", "r.json: rain.drop_volume: expected a number in (0, 1]"},
           {R"("drop_volume": -1e-9)", "r.json: rain.drop_volume: expected a number in (0, 1]"},
           {R"("drop_volume": "big")", "r.json: rain.drop_volume:"},
           {R"("feed_fluid": true, "drop_volume": 2e-6)",
            "r.json: rain.drop_volume: expected at most one particle's water, solver.spacing^3 "
            "= 1e-6 m^3, got 2e-6"},
       }) {
    const std::string e = errorOf(b.keys);
    EXPECT_NE(e.find(b.expect), std::string::npos) << b.keys << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace sph
