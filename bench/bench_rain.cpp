// View-dependent rain (seed 002; docs/benchmarks.md, "View-dependent rain"): the cost per frame of
// the drops' update (move + respawn, CPU, OpenMP) and of drawing their streaks (GL, llvmpipe,
// 960x540, no water) for 10k, 100k and 1M drops and each spawn model, and of the spotlight's hard
// and soft cone edge. The camera pans 90 degrees a second at 30 fps, so drops leave the view and
// are respawned as in a real path.
//   bench_rain --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <memory>

#include "render/gl/GlContext.h"
#include "render/rain/RainRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/Camera.h"
#include "sim/rain/RainSystem.h"

namespace sph {
namespace {

constexpr int kWidth = 960, kHeight = 540;
constexpr float kAspect = static_cast<float>(kWidth) / kHeight;

CameraDesc cameraAtFrame(int frame) {
  CameraDesc c;
  c.position = Vec3(0, 1, 4);
  const double a = frame / 30.0 * M_PI / 2;  // 90 degrees a second
  c.target =
      c.position + Vec3(static_cast<float>(-std::sin(a)), 0, static_cast<float>(-std::cos(a)));
  c.fovYDegrees = 45;
  return c;
}

RainDesc desc(std::int64_t count, std::int64_t spawn) {
  RainDesc d;
  d.count = static_cast<std::size_t>(count);
  d.near = 0.1f, d.far = 5;
  d.spawn = static_cast<RainSpawn>(spawn);
  d.region.lo = Vec3(-5, -1, -5), d.region.hi = Vec3(5, 4, 5);
  return d;
}

// args: drops, spawn (0 view, 1 box, 2 region)
void RainUpdate(benchmark::State& state) {
  rain::RainSystem r(desc(state.range(0), state.range(1)), kAspect);
  r.reset(cameraAtFrame(0));
  int frame = 0;
  for (auto _ : state) r.update(cameraAtFrame(++frame), 1.0f / 30);
  state.counters["drops/s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * state.range(0)), benchmark::Counter::kIsRate);
}
BENCHMARK(RainUpdate)
    ->ArgsProduct({{10000, 100000, 1000000}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond);

std::unique_ptr<render::gl::GlContext> context;

// args: drops, spotlight (0 none, 1 hard cone, 2 soft edge + falloff). Upload + draw + read back.
void RainDraw(benchmark::State& state) {
  if (!context)
    context = std::make_unique<render::gl::GlContext>(render::gl::GlContext::headless());
  RainDesc d = desc(state.range(0), 0);
  if (state.range(1) > 0) {
    SpotlightDesc l;
    l.position = Vec3(0, 4, 0), l.height = 5, l.baseRadius = 3;
    l.colour = Vec3(1, 0.2f, 0.2f);
    if (state.range(1) == 2) l.softEdge = 0.3f, l.falloff = true;
    d.spotlight = l;
  }
  rain::RainSystem r(d, kAspect);
  r.reset(cameraAtFrame(0));
  render::rain::RainRenderer layer(d);
  render::splat::SplatRenderer renderer(kWidth, kHeight);
  renderer.setLayers({&layer});
  const render::splat::SplatFrame none;
  for (auto _ : state) {
    layer.setDrops(r);
    benchmark::DoNotOptimize(renderer.render(none, render::splat::SplatKind::Point,
                                             cameraAtFrame(0), render::splat::Lighting{}));
  }
}
BENCHMARK(RainDraw)
    ->ArgsProduct({{0, 10000, 100000, 1000000}, {0}})
    ->Args({100000, 1})
    ->Args({100000, 2})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sph

BENCHMARK_MAIN();
