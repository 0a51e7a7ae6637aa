// Micro-benchmarks of the SPH stage on the shipped dam break (same scene as the tests), at a
// spacing that gives the particle count in the benchmark's name:
//   NeighbourGrid/build   counting sort of the fluid by cell
//   NeighbourGrid/query   visiting every neighbour of every particle (the loop shape of a pass)
//   Step                  one full adaptive step, reported as particle-steps per second
// Run: build/release/bench/bench_sph --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "io/scene/SceneLoader.h"
#include "sim/Parallel.h"
#include "sim/run/Simulation.h"

namespace {

// Spacing of the dam break (a = 0.146 m column, 2a high, 0.0584 m wide) for about n particles.
std::string spacingFor(double n) {
  const double volume = 0.146 * 0.292 * 0.0584;
  return "solver.spacing=" + std::to_string(std::cbrt(volume / n));
}

sph::scene::Scene damBreak(double n) {
  return sph::io::scene::loadScene(std::string(SPHSPLAT_SOURCE_DIR) + "/scenes/dam_break.json",
                                   {spacingFor(n)});
}

void NeighbourGridBuild(benchmark::State& state) {
  sph::run::Simulation sim(damBreak(static_cast<double>(state.range(0))));
  sim.step();  // a realistic, slightly disordered state
  const sph::Particles& p = sim.fluid();
  sph::grid::NeighbourGrid grid;
  std::vector<std::uint32_t> order;
  for (auto _ : state) {
    grid.build(p.x.data(), p.y.data(), p.z.data(), p.size(), sim.params().h, order);
    benchmark::DoNotOptimize(order.data());
  }
  state.counters["particles"] = static_cast<double>(p.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * p.size()));
}

void NeighbourGridQuery(benchmark::State& state) {
  sph::run::Simulation sim(damBreak(static_cast<double>(state.range(0))));
  sim.step();
  const sph::Particles& p = sim.fluid();
  sph::grid::NeighbourGrid grid;
  std::vector<std::uint32_t> order;
  grid.build(p.x.data(), p.y.data(), p.z.data(), p.size(), sim.params().h, order);
  std::vector<float> x(p.size()), y(p.size()), z(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    x[i] = p.x[order[i]], y[i] = p.y[order[i]], z[i] = p.z[order[i]];
  const float h2 = sim.params().h * sim.params().h;
  std::vector<std::uint32_t> counts(p.size());
  for (auto _ : state) {
    sph::parallelFor(p.size(), [&](std::size_t i) {
      std::uint32_t c = 0;
      grid.forEachNeighbourRange(
          grid.cellOf(x[i], y[i], z[i]), [&](std::uint32_t b, std::uint32_t e) {
            for (std::uint32_t j = b; j < e; ++j) {
              const float dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
              c += dx * dx + dy * dy + dz * dz < h2;
            }
          });
      counts[i] = c;
    });
    benchmark::DoNotOptimize(counts.data());
  }
  double mean = 0;
  for (std::uint32_t c : counts) mean += c;
  state.counters["particles"] = static_cast<double>(p.size());
  state.counters["neighbours"] = mean / static_cast<double>(p.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * p.size()));
}

void Step(benchmark::State& state) {
  sph::run::Simulation sim(damBreak(static_cast<double>(state.range(0))));
  sim.step();
  for (auto _ : state) sim.step();
  state.counters["particles"] = static_cast<double>(sim.fluid().size());
  state.counters["threads"] = sph::threadCount();
  state.counters["particle_steps_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * sim.fluid().size()), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(NeighbourGridBuild)
    ->Arg(20000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(NeighbourGridQuery)
    ->Arg(20000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(Step)
    ->Arg(20000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(5.0);

BENCHMARK_MAIN();
