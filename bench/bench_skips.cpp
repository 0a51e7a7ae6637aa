// The cost of the work a scene skips (DESIGN.md, "What a scene does not need is not run";
// docs/benchmarks.md, "What a scene skips"), measured directly where no option switches a skip
// off: what the skipped work would cost if it ran. scripts/bench_skips.py puts these next to the
// time per step of the same scene.
//   GlContext/headless      create + destroy a headless OpenGL context (EGL; llvmpipe here):
//                           what a scene without render or cdt-gl collision does not pay
//   Boundary/sample         sample the walls and bin them (the boundary part of the setup), what
//                           each step would pay if boundaries were re-sampled every step
//   Simulation/setup        the whole setup (derived constants, boundary, static boundary
//                           density, fluid lattice)
//   Simulation/step         one step of the same scene, for the ratio
//   Splats/...              building one frame's quad splats on the CPU
//   (render/splat/SplatBuilder.h):
//                           surface particles only (the default) against every particle
//                           (surface threshold 1.49 x the mean density: all count as surface),
//                           and a view that frames a third of the tank (the rest is culled)
// Run: build/release/bench/bench_skips --benchmark_format=json
#include <benchmark/benchmark.h>

#include <unistd.h>
#include <fstream>
#include <string>

#include "io/scene/SceneLoader.h"
#include "render/gl/GlContext.h"
#include "render/splat/DensityField.h"
#include "render/splat/SplatBuilder.h"
#include "sim/run/Simulation.h"
#include "sim/cdt/CdtCamera.h"

namespace {

// The dam break at a / dx = 20 (6400 fluid, ~24k boundary particles), as in docs/benchmarks.md.
sph::scene::Scene damBreak() {
  return sph::io::scene::loadScene(std::string(SPHSPLAT_SOURCE_DIR) + "/scenes/dam_break.json",
                                   {"solver.spacing=0.0073"});
}

double residentMb() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

void GlContextHeadless(benchmark::State& state) {
  const double before = residentMb();
  double after = before;
  for (auto _ : state) {
    try {
      sph::render::gl::GlContext context = sph::render::gl::GlContext::headless();
      benchmark::DoNotOptimize(&context);
      after = std::max(after, residentMb());
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
  }
  // Memory a context leaves mapped (driver, shader compiler) beyond what the process had.
  state.counters["rss_mb"] = after - before;
}

void BoundarySample(benchmark::State& state) {
  const sph::scene::Scene scene = damBreak();
  const sph::scene::SolverParams& s = scene.solver;
  std::size_t n = 0;
  for (auto _ : state) {
    sph::solver::Boundary b(scene.boundaries, scene.domain, s.spacing, s.wallLayers(),
                            s.supportRadius());
    n = b.particles().size();
    benchmark::DoNotOptimize(&b);
  }
  state.counters["boundary_particles"] = static_cast<double>(n);
}

void SimulationSetup(benchmark::State& state) {
  const sph::scene::Scene scene = damBreak();
  for (auto _ : state) {
    sph::run::Simulation sim(scene);
    benchmark::DoNotOptimize(&sim);
  }
}

void SimulationStep(benchmark::State& state) {
  sph::run::Simulation sim(damBreak());
  sim.advanceTo(0.05);  // a moving, disordered state
  for (auto _ : state) sim.step();
  state.counters["particles"] = static_cast<double>(sim.fluid().size());
}

// Quad splats of the dam break at t = 0.2 s (the surge running along the floor). Args: surface
// threshold x 100 (0 = automatic), vertical field of view in degrees.
void Splats(benchmark::State& state) {
  sph::run::Simulation sim(damBreak());
  sim.advanceTo(0.2);
  const sph::Particles& p = sim.fluid();
  const float spacing = sim.scene().solver.spacing;
  sph::render::splat::SplatParams params;
  params.surfaceThreshold = static_cast<float>(state.range(0)) / 100.0f;
  const sph::render::splat::DensityField field(p.x.data(), p.y.data(), p.z.data(), p.size(),
                                               spacing, params.kernelRadius);
  // The scene's camera looks at the tank's middle; a narrow field of view keeps part of it.
  const sph::Vec3 eye(0.5f, 0.32f, 0.62f), target(0.27f, 0.08f, 0.03f);
  const sph::scene::Mat4 projView = sph::scene::multiply(
      sph::scene::perspective(static_cast<float>(state.range(1)), 4.0f / 3.0f, 0.01f, 10.0f),
      sph::scene::lookAt(eye, target, sph::Vec3::UnitY()));
  sph::render::splat::SplatFrame frame;
  for (auto _ : state) {
    frame = sph::render::splat::buildSplats(field, params, sph::render::splat::SplatKind::Quad,
                                            projView, eye);
    benchmark::DoNotOptimize(frame.quads.data());
  }
  state.counters["particles"] = static_cast<double>(frame.particles);
  state.counters["surface"] = static_cast<double>(frame.surface);
  state.counters["culled"] = static_cast<double>(frame.culled);
  state.counters["splats"] = static_cast<double>(frame.quads.size() / 5);
}

}  // namespace

BENCHMARK(Splats)
    ->Name("Splats/surface")
    ->Args({0, 60})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(Splats)
    ->Name("Splats/every_particle")
    ->Args({149, 60})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(Splats)
    ->Name("Splats/surface_narrow_view")
    ->Args({0, 12})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(GlContextHeadless)
    ->Name("GlContext/headless")
    ->Iterations(5)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BoundarySample)
    ->Name("Boundary/sample")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(SimulationSetup)
    ->Name("Simulation/setup")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(SimulationStep)
    ->Name("Simulation/step")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);

BENCHMARK_MAIN();
