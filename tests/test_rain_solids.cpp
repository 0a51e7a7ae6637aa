// Drops against thin solids (seed 002's respawn, docs/rain.md, "Replay"): a drop falls ~10 cm a
// frame, further than a tray's floor or a cup's wall is thick, so testing where its move ends
// lets it through. Every move a drop keeps is checked here against the solids by marching its
// segment in fine steps, independently of how the rain tests it. CPU only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "sim/Particles.h"
#include "sim/rain/RainStepper.h"
#include "sim/rain/RainSystem.h"
#include "sim/scene/Solid.h"
#include "tests/RainTestScenes.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using rain::RainSystem;
using test::kAspect;
using test::lookingAlongZ;
using test::rainDesc;

// Whether the segment a..b meets a solid, sampled every `step` (m) and at both ends; the
// segments whose bounding box misses every solid's box are skipped (planes: never).
bool marchMeetsSolid(const Vec3& a, const Vec3& b, const std::vector<scene::Solid>& solids,
                     float step) {
  const int samples = std::max(1, static_cast<int>((b - a).norm() / step) + 1);
  for (const scene::Solid& s : solids) {
    const Aabb box = s.bounds();
    if (!box.empty() && ((a.cwiseMax(b).array() < box.lo.array()).any() ||
                         (a.cwiseMin(b).array() > box.hi.array()).any()))
      continue;
    for (int k = 0; k <= samples; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(samples);
      if (s.distance(a + t * (b - a)) < 0) return true;
    }
  }
  return false;
}

// The moves of one update that kept their drop (same respawn count) and passed through a solid.
std::size_t crossings(const std::vector<Vec3>& before, const std::vector<std::uint32_t>& gensBefore,
                      const RainSystem& r, const std::vector<scene::Solid>& solids, float step,
                      std::size_t& kept) {
  std::size_t through = 0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    if (r.generations()[i] != gensBefore[i]) continue;
    ++kept;
    through += marchMeetsSolid(before[i], r.positions()[i], solids, step);
  }
  return through;
}

// A 1 cm slab across the whole rain space and drops falling 10 cm a frame: every drop that
// reaches it is respawned, none is found below it having kept its respawn count.
TEST(RainSolids, NoDropPassesThroughAOneCentimetreSlabInATenCentimetreMove) {
  const scene::CameraDesc c = lookingAlongZ();
  scene::BoundaryShape slab;
  slab.kind = scene::BoundaryShape::Kind::Block;
  slab.lo = Vec3(-10, 0.495f, -10), slab.hi = Vec3(10, 0.505f, 10);
  const std::vector<scene::Solid> solids = {scene::Solid(slab, 0.01f)};
  rain::RainObstacles obstacles;
  obstacles.solids = &solids;
  scene::RainDesc d = rainDesc(scene::RainSpawn::View);
  d.fallSpeed = 3, d.wind = Vec3(0.3f, 0, 0);  // 0.1 m a frame at 30 fps, as in rain_pour
  RainSystem r(d, kAspect);
  r.reset(c, obstacles);
  std::size_t through = 0, kept = 0;
  for (int f = 0; f < 30; ++f) {
    const std::vector<Vec3> before = r.positions();
    const std::vector<std::uint32_t> gens = r.generations();
    r.update(c, 1.0f / 30, obstacles);
    through += crossings(before, gens, r, solids, 0.0005f, kept);
  }
  std::printf("%zu of %zu kept moves passed through the slab; %llu drops hit it\n", through, kept,
              static_cast<unsigned long long>(r.counters().hitSolid));
  EXPECT_EQ(through, 0u);
  EXPECT_GT(r.counters().hitSolid, 1000u);
}

// scenes/rain_pour.json's rain over its tray (floor 1 cm thick) and cup (walls 1 cm) for 1 s of
// its camera path, without water: no kept move passes through either.
TEST(RainSolids, NoDropPassesThroughRainPoursTrayOrCup) {
  const scene::Scene scene = test::shippedScene("rain_pour");
  auto stepper = rain::RainStepper::create(scene, rain::RainStepper::sceneAspect(scene));
  ASSERT_NE(stepper, nullptr);
  std::vector<scene::Solid> solids;
  for (const scene::BoundaryShape& b : scene.boundaries)
    solids.emplace_back(b, scene.solver.wallThickness());
  const Particles dry;
  stepper->advanceTo(0, dry);
  std::size_t through = 0, kept = 0;
  const int frames = static_cast<int>(scene.output.fps);
  for (int f = 1; f <= frames; ++f) {
    const RainSystem& r = stepper->system();
    const std::vector<Vec3> before = r.positions();
    const std::vector<std::uint32_t> gens = r.generations();
    stepper->advanceTo(static_cast<double>(f) / scene.output.fps, dry);
    through += crossings(before, gens, r, solids, 0.0005f, kept);
  }
  std::printf("rain_pour, 1 s: %zu of %zu kept moves passed through a solid; %llu drops hit one\n",
              through, kept,
              static_cast<unsigned long long>(stepper->system().counters().hitSolid));
  EXPECT_EQ(through, 0u);
  EXPECT_GT(stepper->system().counters().hitSolid, 1000u);
}

}  // namespace
}  // namespace sph
