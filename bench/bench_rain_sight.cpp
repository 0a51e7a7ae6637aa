// The visible budget measured (seed 002's rain; docs/rain.md, "The visible budget";
// docs/notes/2026-11-29-rain-visible-budget.md): the share of the budget the eye sees, from the
// geometry (tests/RainSight.h), on rain_pour's camera path and a stress path, for the depth image
// (rain.occlusion "depth_map") and the paper's frustum alone ("none"); and what deciding a
// drop's visibility costs by the depth image and by exact rays. Built into bench_rain.
//   bench_rain --benchmark_filter='RainVisible|RainSightCost'
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/scene/SceneLoader.h"
#include "sim/rain/EyeDepth.h"
#include "sim/rain/RainStepper.h"
#include "sim/rain/RainSystem.h"
#include "tests/RainSight.h"

namespace sph {
namespace {

const scene::Scene& rainPour() {
  static const scene::Scene s =
      io::scene::loadScene(std::string(SPHSPLAT_SOURCE_DIR) + "/scenes/rain_pour.json");
  return s;
}

// args: path (0 rain_pour's camera path, 1 the stress path: tests/RainSight.h), rain.occlusion
// (0 "depth_map", 1 "none"), drops. One iteration = the whole path from a reset; counters: the
// least and mean share of the budget the eye sees over the frames, the least in the frustum, the
// update's time per frame, hidden respawns per frame and parked drops.
void RainVisible(benchmark::State& state) {
  const auto path = static_cast<test::SightPath>(state.range(0));
  const auto occlusion = static_cast<scene::RainOcclusion>(state.range(1));
  test::SightTrack t;
  for (auto _ : state) t = test::trackSight(rainPour(), occlusion, path, state.range(2));
  const double frames = test::sightFrames(path);
  state.counters["min_visible"] = t.minVisible;
  state.counters["mean_visible"] = t.meanVisible;
  state.counters["min_in_view"] = t.minInView;
  state.counters["update_ms"] = 1e3 * t.updateSeconds / frames;
  state.counters["hidden/frame"] = static_cast<double>(t.counters.hidden) / frames;
  state.counters["parked"] = static_cast<double>(t.counters.parked);
}
BENCHMARK(RainVisible)
    ->ArgsProduct({{0, 1}, {0, 1}, {8000, 100000}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// args: method (0 the depth image: built once, then one look-up a drop; 1 rays: each drop's eye
// ray cut exactly against the solids (Solid::segmentEntry) and sampled every quarter water cell
// against the water's cells), drops, the image's rows (EyeDepth::kRows the rain's). Drops uniform
// in rain_pour's first rain space (occlusion "none"), its solids and stand-in water. One iteration
// decides every drop once; counters: the share each method calls visible, and the share of the
// first 20,000 where it disagrees with the geometry's measure (tests/RainSight.h): called visible
// but hidden, and the other way.
void RainSightCost(benchmark::State& state) {
  const scene::Scene& scene = rainPour();
  scene::RainDesc d = *scene.rain;
  d.occlusion = scene::RainOcclusion::None, d.count = static_cast<std::size_t>(state.range(1));
  std::vector<scene::Solid> solids;
  for (const scene::BoundaryShape& b : scene.boundaries)
    solids.emplace_back(b, scene.solver.wallThickness());
  const std::vector<Vec3> water = test::rainPourWater(scene);
  const rain::WaterCells cells(water, rain::RainStepper::waterCell(scene));
  const scene::CameraDesc camera = *scene.camera;
  rain::RainSystem r(d, rain::RainStepper::sceneAspect(scene));
  r.reset(camera);
  const rain::RainSpace& s = r.space();
  const std::vector<Vec3>& drops = r.positions();
  std::vector<std::uint8_t> seen(drops.size());
  rain::EyeDepth image;
  auto rayVisible = [&](const Vec3& p) {
    if (rain::firstSolidEntry(s.eye, p, solids) <= 1) return false;
    if (!cells.near(s.eye, p)) return true;
    const float quarter = 0.25f * cells.cell();
    const int n = std::max(1, static_cast<int>(std::ceil((p - s.eye).norm() / quarter)));
    for (int k = 1; k <= n; ++k)
      if (cells.contains(s.eye + (static_cast<float>(k) / static_cast<float>(n)) * (p - s.eye)))
        return false;
    return true;
  };
  const auto n = static_cast<std::ptrdiff_t>(drops.size());
  for (auto _ : state) {
    if (state.range(0) == 0) {
      image.build(s, &solids, &cells, static_cast<int>(state.range(2)));
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i)
        seen[static_cast<std::size_t>(i)] = image.visible(drops[static_cast<std::size_t>(i)]);
    } else {
#pragma omp parallel for schedule(dynamic, 1024)
      for (std::ptrdiff_t i = 0; i < n; ++i)
        seen[static_cast<std::size_t>(i)] = rayVisible(drops[static_cast<std::size_t>(i)]);
    }
    benchmark::DoNotOptimize(seen.data());
  }
  const test::EyeSight sight(solids, water, scene.solver.spacing);
  std::size_t visible = 0, falseSeen = 0, falseHidden = 0;
  const std::size_t checked = std::min<std::size_t>(drops.size(), 20000);
  for (std::size_t i = 0; i < drops.size(); ++i) {
    visible += seen[i];
    if (i >= checked) continue;
    const bool truth = sight.visible(camera.position, drops[i]);
    falseSeen += seen[i] && !truth, falseHidden += !seen[i] && truth;
  }
  state.counters["visible"] = static_cast<double>(visible) / static_cast<double>(drops.size());
  state.counters["seen_but_hidden"] = static_cast<double>(falseSeen) / static_cast<double>(checked);
  state.counters["hidden_but_seen"] =
      static_cast<double>(falseHidden) / static_cast<double>(checked);
}
BENCHMARK(RainSightCost)
    ->ArgsProduct({{0}, {8000, 100000, 1000000}, {rain::EyeDepth::kRows}})
    ->ArgsProduct({{1}, {8000, 100000, 1000000}, {0}})
    ->ArgsProduct({{0}, {8000}, {32, 128, 256}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sph
