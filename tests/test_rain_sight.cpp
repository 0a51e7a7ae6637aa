// The visible budget (seed 002's rain, docs/rain.md, "The visible budget"): with rain.occlusion
// "depth_map" the drops are placed and kept only where the eye sees them, in front of the solids
// and the water; the paper's frustum-only placement ("none") spends most of rain_pour's budget
// behind its tray and cup. Measured by tests/RainSight.h from the geometry (the solids' signed
// distance marched along the eye ray, the water particles' spheres), not by the depth image the
// rain uses, on rain_pour's camera path and on a stress path with a 90-degree turn within one
// frame interval. CPU only.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "sim/rain/RainStepper.h"
#include "sim/rain/RainSystem.h"
#include "tests/RainSight.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using test::SightPath;
using test::SightTrack;

void print(const char* what, const SightTrack& t) {
  std::printf(
      "%s: visible min %.4f mean %.4f, in view min %.4f; respawns: left %llu, solid %llu, water "
      "%llu, hidden %llu; parked %llu; updates %.1f ms\n",
      what, t.minVisible, t.meanVisible, t.minInView,
      static_cast<unsigned long long>(t.counters.leftSpace),
      static_cast<unsigned long long>(t.counters.hitSolid),
      static_cast<unsigned long long>(t.counters.hitWater),
      static_cast<unsigned long long>(t.counters.hidden),
      static_cast<unsigned long long>(t.counters.parked), 1e3 * t.updateSeconds);
}

// The measure itself: a point behind a slab or a particle is hidden, one in front is not.
TEST(RainSight, TheMeasureSeesTheSolidsAndTheWaterOnTheEyeRay) {
  scene::BoundaryShape slab;
  slab.kind = scene::BoundaryShape::Kind::Block;
  slab.lo = Vec3(-1, -0.005f, -1), slab.hi = Vec3(1, 0.005f, 1);
  const test::EyeSight sight({scene::Solid(slab, 0.01f)}, {Vec3(0, 1, 0)}, 0.01f);
  const Vec3 eye(0, 2, 0.3f);
  EXPECT_TRUE(sight.visible(eye, Vec3(0.5f, 0.5f, 0)));
  EXPECT_FALSE(sight.visible(eye, Vec3(0.5f, -0.5f, 0)));  // under the slab
  // The ray from the eye through the particle, 1.5 times as far, and 3 cm beside that.
  EXPECT_FALSE(sight.visible(eye, Vec3(0, 0.5f, -0.15f)));          // behind the particle
  EXPECT_TRUE(sight.visible(eye, Vec3(0.03f, 0.5f, -0.15f)));       // beside it
  EXPECT_FALSE(sight.visible(Vec3(0, 0.5f, 0), Vec3(0, 1.5f, 0)));  // through it
}

TEST(RainSight, OnRainPourTheBudgetIsVisibleAtEveryFrame) {
  const scene::Scene scene = test::shippedScene("rain_pour");
  const SightTrack eye =
      test::trackSight(scene, scene::RainOcclusion::DepthMap, SightPath::RainPour);
  const SightTrack paper = test::trackSight(scene, scene::RainOcclusion::None, SightPath::RainPour);
  print("rain_pour, depth_map", eye);
  print("rain_pour, none", paper);
  EXPECT_GE(eye.minVisible, 0.95);
  EXPECT_EQ(eye.minInView, 1.0);
  EXPECT_EQ(eye.counters.parked, 0u);
  EXPECT_GT(eye.counters.hidden, 0u);
  // The paper's placement fills the frustum, most of it hidden: the measure can fail.
  EXPECT_EQ(paper.minInView, 1.0);
  EXPECT_LT(paper.meanVisible, 0.6);
  EXPECT_EQ(paper.counters.hidden, 0u);
}

TEST(RainSight, ThroughSnapTurnsZoomAndDollyTheBudgetIsVisibleAtEveryFrame) {
  const scene::Scene scene = test::shippedScene("rain_pour");
  const SightTrack eye = test::trackSight(scene, scene::RainOcclusion::DepthMap, SightPath::Stress);
  const SightTrack paper = test::trackSight(scene, scene::RainOcclusion::None, SightPath::Stress);
  print("stress path, depth_map", eye);
  print("stress path, none", paper);
  for (std::size_t f = 0; f < eye.visible.size(); ++f)
    EXPECT_GE(eye.visible[f], 0.95) << "frame " << f;
  EXPECT_EQ(eye.minInView, 1.0);
  EXPECT_EQ(eye.counters.parked, 0u);
  EXPECT_LT(paper.minVisible, 0.6);
  // The first frame after the snap turn (frame 10) sees the whole budget, placed in its update.
  EXPECT_GE(eye.visible[10], 0.95);
}

}  // namespace
}  // namespace sph
