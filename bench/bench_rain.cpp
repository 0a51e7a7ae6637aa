// View-dependent rain (seed 002; docs/benchmarks.md, "View-dependent rain"): the cost per frame of
// the drops' update (move + respawn, CPU, OpenMP), of drawing their streaks (rain.draw "cpu" and
// "triangles", llvmpipe, 960x540, no water) for 10k, 100k and 1M drops, of the spotlight's hard
// and soft cone edge, and of whole frames (update + draw) for 1k to 1M drops and each spawn model,
// at the scene defaults (RainFrameDefault) and at equal drops seen (RainFrameSeen, the paper's
// Fig. 8 as its claim reads); the update also with a tray and a cup in the way.
// The camera pans 90 degrees a second at 30 fps, so drops leave the view and are respawned as in a
// real path. The paper's claims measured (the budget in view along camera paths, Table 1's random
// number methods) are bench_rain_paper.cpp, built into the same program.
//   bench_rain --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "bench/RainBenchScenes.h"
#include "render/gl/GlContext.h"
#include "render/gl/GlHandle.h"
#include "render/rain/ComposeOver.h"
#include "render/rain/RainRenderer.h"
#include "render/rain/StreakImages.h"
#include "render/rain/StreakRaster.h"
#include "render/rain/StreakSums.h"
#include "render/splat/SplatRenderer.h"
#include "sim/rain/RainSystem.h"
#include "sim/scene/Camera.h"

namespace sph {
namespace {

using bench::cameraAtFrame;
using bench::desc;
using bench::kAspect;
using bench::kHeight;
using bench::kWidth;

// args: drops, spawn (0 view, 1 box, 2 region)
void RainUpdate(benchmark::State& state) {
  rain::RainSystem r(desc(state.range(0), state.range(1)), kAspect);
  r.reset(cameraAtFrame(0));
  int frame = 0;
  const rain::RainCounters before = r.counters();
  for (auto _ : state) r.update(cameraAtFrame(++frame), 1.0f / 30);
  // Respawns per frame and sphere (or box) samples per respawn: what the update's time is spent on.
  const rain::RainCounters& c = r.counters();
  const double respawns = static_cast<double>(c.accepted - before.accepted);
  state.counters["respawns/frame"] = respawns / static_cast<double>(state.iterations());
  state.counters["samples/respawn"] =
      respawns > 0 ? (respawns + static_cast<double>(c.rejected - before.rejected)) / respawns : 0;
  // `uniform` view: the cube's candidates, the sphere's samples and those outside it.
  state.counters["candidates/respawn"] =
      respawns > 0 ? (respawns + static_cast<double>(c.rejected - before.rejected) +
                      static_cast<double>(c.outsideSphere - before.outsideSphere)) /
                         respawns
                   : 0;
  state.counters["drops/s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * state.range(0)), benchmark::Counter::kIsRate);
}
BENCHMARK(RainUpdate)
    ->ArgsProduct({{10000, 100000, 1000000}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond);

// args: drops. The `view` update of RainUpdate with bench::solids() in the way: what testing each
// drop's move against the solids costs. Counter: drops that hit a solid per frame.
void RainUpdateSolids(benchmark::State& state) {
  rain::RainSystem r(desc(state.range(0), 0), kAspect);
  const std::vector<scene::Solid> solids = bench::solids();
  rain::RainObstacles obstacles;
  obstacles.solids = &solids;
  r.reset(cameraAtFrame(0), obstacles);
  int frame = 0;
  const std::uint64_t before = r.counters().hitSolid;
  for (auto _ : state) r.update(cameraAtFrame(++frame), 1.0f / 30, obstacles);
  state.counters["hits/frame"] =
      static_cast<double>(r.counters().hitSolid - before) / static_cast<double>(state.iterations());
}
BENCHMARK(RainUpdateSolids)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

std::unique_ptr<render::gl::GlContext> context;

// `d`'s drops reset at the first camera, their layer, and the 960x540 frame (no water) it is
// drawn into; makes the headless context on first use.
struct RainFrameDraw {
  static const scene::RainDesc& withContext(const scene::RainDesc& d) {
    if (!context)
      context = std::make_unique<render::gl::GlContext>(render::gl::GlContext::headless());
    return d;
  }
  explicit RainFrameDraw(const scene::RainDesc& d)
      : drops(withContext(d), kAspect), layer(d), renderer(kWidth, kHeight) {
    drops.reset(cameraAtFrame(0));
    renderer.setLayers({&layer});
  }
  // Uploads the drops and draws them: upload + draw + read back.
  render::frame::RenderImage draw(const scene::CameraDesc& camera) {
    layer.setDrops(drops);
    return renderer.render(render::splat::SplatFrame{}, render::splat::SplatKind::Point, camera,
                           render::frame::Lighting{});
  }
  rain::RainSystem drops;
  render::rain::RainRenderer layer;
  render::splat::SplatRenderer renderer;
};

// Fragments per drop of a frame just drawn: the rasteriser's count ("cpu"), or GL's
// GL_SAMPLES_PASSED over `frame()` ("triangles"; every one passes: nothing else writes depth).
template <class Frame>
double fragmentsPerDrop(const render::rain::RainRenderer& layer, Frame frame) {
  GLuint64 fragments = 0;
  if (layer.raster() != nullptr) {
    frame();
    fragments = layer.raster()->fragments();
  } else {
    auto query = render::gl::Query::create(GL_SAMPLES_PASSED);
    glBeginQuery(GL_SAMPLES_PASSED, query.id());
    frame();
    glEndQuery(GL_SAMPLES_PASSED);
    glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &fragments);
  }
  return layer.drops() > 0 ? static_cast<double>(fragments) / static_cast<double>(layer.drops())
                           : 0.0;
}

// args: drops, spotlight (0 none, 1 hard cone, 2 soft edge + falloff, 3 profile: streaks of no
// size), rain.draw (0 "cpu" with every streak exact, rain.lod_width 0; 1 "triangles"). Upload +
// draw + read back.
void RainDraw(benchmark::State& state) {
  scene::RainDesc d = desc(state.range(0), 0);
  if (state.range(1) > 0) {
    scene::SpotlightDesc l;
    l.position = Vec3(0, 4, 0), l.height = 5, l.baseRadius = 3;
    l.colour = Vec3(1, 0.2f, 0.2f);
    if (state.range(1) == 2) l.softEdge = 0.3f, l.falloff = true;
    d.spotlight = l;
  }
  if (state.range(1) == 3) d.exposure = 0, d.dropWidth = 0;  // profile: no fragments
  d.draw = static_cast<sph::scene::RainDraw>(state.range(2));
  d.lodWidth = 0;  // "cpu": every streak exact, the triangles' picture
  RainFrameDraw rain(d);
  auto frame = [&] { return rain.draw(cameraAtFrame(0)); };
  state.counters["fragments/drop"] = fragmentsPerDrop(rain.layer, frame);
  for (auto _ : state) benchmark::DoNotOptimize(frame());
}
BENCHMARK(RainDraw)
    ->ArgsProduct({{0, 10000, 100000, 1000000}, {0}, {0, 1}})
    ->Args({100000, 1, 0})
    ->Args({100000, 2, 0})
    ->Args({1000000, 1, 0})
    ->Args({1000000, 2, 0})
    ->Args({100000, 1, 1})
    ->Args({100000, 2, 1})
    ->Args({100000, 3, 1})
    ->Unit(benchmark::kMillisecond);

// The CPU rasteriser of rain.draw "cpu" alone (render/rain/StreakRaster.h, no GL: what RainDraw's
// "cpu" cases spend besides the depth read-back, the layer upload and the blend pass), against an
// empty depth buffer. args: drops, rain.lod_width in hundredths of a pixel (0: every streak exact).
// `farTier`: rain.far_tier (RainRasterSums: "sums").
void rainRaster(benchmark::State& state, scene::RainFarTier farTier) {
  scene::RainDesc d = desc(state.range(0), 0);
  d.lodWidth = static_cast<float>(state.range(1)) / 100;
  d.farTier = farTier;
  rain::RainSystem r(d, kAspect);
  r.reset(cameraAtFrame(0));
  render::rain::StreakRaster raster(d, render::rain::generateStreakImages(8, 16, 64, d.seed));
  const std::vector<float> depth(static_cast<std::size_t>(kWidth) * kHeight, 1.0f);
  const render::rain::StreakView view{cameraFrame(cameraAtFrame(0), kAspect), kWidth, kHeight};
  const render::rain::StreakDrops drops{&r.positions(), &r.layers(), r.velocity()};
  for (auto _ : state) {
    raster.draw(view, drops, Vec3(0.5f, 0.5f, 0.5f), depth.data());
    benchmark::DoNotOptimize(raster.layer().data());
  }
  state.counters["fragments/drop"] =
      static_cast<double>(raster.fragments()) / static_cast<double>(state.range(0));
  // A 32-bit FNV-1a hash of the layer's bytes: two builds drew the same picture, bit for bit, when
  // it is the same (a change meant to be only faster is checked with it).
  std::uint32_t hash = 2166136261u;
  const auto* bytes = reinterpret_cast<const unsigned char*>(raster.layer().data());
  for (std::size_t i = 0; i < raster.layer().size() * sizeof(float); ++i)
    hash = (hash ^ bytes[i]) * 16777619u;
  state.counters["layer_hash"] = static_cast<double>(hash);
}
void RainRaster(benchmark::State& state) {
  rainRaster(state, scene::RainFarTier::Lines);
}
BENCHMARK(RainRaster)
    ->ArgsProduct({{10000, 100000, 1000000}, {0}})
    ->Args({1000000, 50})
    ->Args({1000000, 100})
    ->Unit(benchmark::kMillisecond);
void RainRasterSums(benchmark::State& state) {
  rainRaster(state, scene::RainFarTier::Sums);
}
BENCHMARK(RainRasterSums)
    ->Args({1000000, 50})
    ->Args({1000000, 100})
    ->Args({1000000, 200})
    ->Args({1000000, 400})
    ->Args({1000000, 800})
    ->Unit(benchmark::kMillisecond);

// The sums' resolve alone (render/rain/StreakSums.h): `range(0)` upright lines of 1-25 rows at
// random over the 960x540 frame (1,000,000: ~13 lines a pixel, each pixel touched, near the bench
// camera's 1.0 M runs), added once, then resolved each iteration (it leaves its strips zeroed and
// keeps the runs). args: lines.
void RainSumsResolve(benchmark::State& state) {
  const int threads = omp_get_max_threads();
  const std::vector<float> depth(static_cast<std::size_t>(kWidth) * kHeight, 1.0f);
  std::vector<float> layer(4 * depth.size());
  render::rain::StreakSums sums;
  sums.begin(kWidth, kHeight, depth.data(), threads);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 1);
  for (std::int64_t i = 0; i < state.range(0); ++i) {
    const int first = static_cast<int>(u(rng) * (kHeight - 1));
    const int end = std::min(kHeight, first + 1 + static_cast<int>(u(rng) * 25));
    render::rain::Line l{};
    l.xt = u(rng) * (kWidth - 1) + 0.5f, l.yt = static_cast<float>(first), l.zt = 0.5f;
    l.invDy = 1.0f / static_cast<float>(end - first), l.coverage = 0.5f;
    l.first = first, l.end = end;
    const Vec3 c(u(rng), u(rng), u(rng));
    sums.add(static_cast<int>(i % threads), l, first, end, c, 0.02f + 0.2f * u(rng));
  }
  for (auto _ : state) {
    sums.resolve(layer.data());
    benchmark::DoNotOptimize(layer.data());
  }
  state.counters["runs"] = static_cast<double>(sums.runs());
}
BENCHMARK(RainSumsResolve)->Arg(1000000)->Unit(benchmark::kMillisecond);

// The CPU path's composite alone (render/rain/ComposeOver.h): a 960x540 layer, every pixel
// touched, over a frame of random bytes (copied back in each iteration, outside the timing).
void RainCompose(benchmark::State& state) {
  const std::size_t pixels = static_cast<std::size_t>(kWidth) * kHeight;
  std::vector<float> layer(4 * pixels);
  std::vector<std::uint8_t> frame(4 * pixels), rgba;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 1);
  for (std::size_t p = 0; p < pixels; ++p) {
    const float t = u(rng);
    for (int k = 0; k < 3; ++k) layer[4 * p + k] = u(rng) * (1 - t);
    layer[4 * p + 3] = t;
  }
  for (auto& b : frame) b = static_cast<std::uint8_t>(rng());
  for (auto _ : state) {
    state.PauseTiming();
    rgba = frame;
    state.ResumeTiming();
    render::rain::composeOver(layer, rgba);
    benchmark::DoNotOptimize(rgba.data());
  }
}
BENCHMARK(RainCompose)->Unit(benchmark::kMillisecond);

// The paper's Fig. 8 layout: a whole frame of rain against the budget - update (move + respawn)
// + upload + draw + read back, 960x540, no water - while the camera pans 90 degrees a second.
// args: drops, spawn (0 view, 1 box, 2 region), rain.draw (0 "cpu", 1 "triangles"),
// rain.lod_width in hundredths of a pixel. `farTier`: rain.far_tier (RainFrameSums: "sums").
void rainFrame(benchmark::State& state, scene::RainFarTier farTier) {
  scene::RainDesc d = desc(state.range(0), state.range(1));
  d.draw = static_cast<sph::scene::RainDraw>(state.range(2));
  d.lodWidth = static_cast<float>(state.range(3)) / 100;
  d.farTier = farTier;
  RainFrameDraw rain(d);
  int frame = 0;
  for (auto _ : state) {
    const scene::CameraDesc camera = cameraAtFrame(++frame);
    rain.drops.update(camera, 1.0f / 30);
    benchmark::DoNotOptimize(rain.draw(camera));
  }
  state.counters["fragments/drop"] = rain.layer.raster()
                                         ? static_cast<double>(rain.layer.raster()->fragments()) /
                                               static_cast<double>(state.range(0))
                                         : 0.0;
}
void RainFrame(benchmark::State& state) {
  rainFrame(state, scene::RainFarTier::Lines);
}
BENCHMARK(RainFrame)
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1, 2}, {0}, {0}})
    ->Args({1000000, 0, 0, 50})
    ->Args({1000000, 0, 0, 100})
    ->Unit(benchmark::kMillisecond);
void RainFrameSums(benchmark::State& state) {
  rainFrame(state, scene::RainFarTier::Sums);
}
BENCHMARK(RainFrameSums)
    ->Args({10000, 0, 0, 800})
    ->Args({100000, 0, 0, 800})
    ->Args({1000000, 0, 0, 50})
    ->Args({1000000, 0, 0, 100})
    ->Args({1000000, 0, 0, 200})
    ->Args({1000000, 0, 0, 400})
    ->Args({1000000, 0, 0, 800})
    ->Unit(benchmark::kMillisecond);

// A whole frame as rainFrame's at the scene's default settings, whatever they are (scene::RainDesc
// as the scene loader leaves it: since 2026-11-29 rain.far_tier "sums" at rain.lod_width 8, and
// rain.occlusion "depth_map"). args: drops, solids (0 none; 1 bench::solids() in the way, so that
// the visible budget's depth image hides part of the rain space and the drops' moves are cut).
void RainFrameDefault(benchmark::State& state) {
  const scene::RainDesc d = desc(state.range(0), 0);
  const std::vector<scene::Solid> solids = bench::solids();
  rain::RainObstacles obstacles;
  if (state.range(1) == 1) obstacles.solids = &solids;
  RainFrameDraw rain(d);
  rain.drops.reset(cameraAtFrame(0), obstacles);
  int frame = 0;
  for (auto _ : state) {
    const scene::CameraDesc camera = cameraAtFrame(++frame);
    rain.drops.update(camera, 1.0f / 30, obstacles);
    benchmark::DoNotOptimize(rain.draw(camera));
  }
}
BENCHMARK(RainFrameDefault)
    ->ArgsProduct({{10000, 100000, 1000000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

// The paper's Fig. 8 at equal drops seen: Fig. 8 times the models at equal budgets, but box and
// region spend most of theirs out of view. Here each model's budget is what puts `seen` drops in
// the rain camera's frustum (what a frame draws; nothing is in the way here) on average over the
// pan: a probe of 100,000 drops along 120 frames of it (a whole turn, not timed) gives the
// model's share in the frustum, and the budget is `seen` / share. Timed, over the same turn: whole
// frames as RainFrameDefault's (default settings). args: drops seen, spawn (0 view, 1 box, 2
// region). Counters: the budget, the drops in the frustum per frame over the timed frames (counted
// with the clock paused), budget / seen.
void RainFrameSeen(benchmark::State& state) {
  const std::int64_t seen = state.range(0), spawn = state.range(1);
  double share = 0;
  {
    const scene::RainDesc probe = desc(100000, spawn);
    rain::RainSystem r(probe, kAspect);
    r.reset(cameraAtFrame(0));
    for (int f = 1; f <= 120; ++f) {
      r.update(cameraAtFrame(f), 1.0f / 30);
      share += static_cast<double>(bench::dropsInFrustum(r, cameraAtFrame(f), probe)) / 120 /
               static_cast<double>(probe.count);
    }
  }
  const scene::RainDesc d =
      desc(static_cast<std::int64_t>(std::llround(static_cast<double>(seen) / share)), spawn);
  RainFrameDraw rain(d);
  int frame = 0;
  double inView = 0;
  for (auto _ : state) {
    const scene::CameraDesc camera = cameraAtFrame(++frame);
    rain.drops.update(camera, 1.0f / 30);
    benchmark::DoNotOptimize(rain.draw(camera));
    state.PauseTiming();
    inView += static_cast<double>(bench::dropsInFrustum(rain.drops, camera, d));
    state.ResumeTiming();
  }
  state.counters["budget"] = static_cast<double>(d.count);
  state.counters["seen/frame"] = inView / static_cast<double>(state.iterations());
  state.counters["budget/seen"] =
      static_cast<double>(d.count) * static_cast<double>(state.iterations()) / inView;
}
BENCHMARK(RainFrameSeen)
    ->ArgsProduct({{10500, 100000}, {0, 1, 2}})
    ->Iterations(120)  // the probe's whole turn, so the drops seen average over the same frames
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sph

BENCHMARK_MAIN();
