// The paper's claims about view-dependent rain measured (seed 002; docs/benchmarks.md,
// "View-dependent rain"): the share of the budget inside the view frustum along camera paths, and
// its Table 1, the random number methods for spawning. Built into bench_rain, whose other
// benchmarks time the update and the drawing.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <vector>

#include "bench/RainBenchScenes.h"
#include "sim/scene/Camera.h"
#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSystem.h"
#include "sim/rain/ViewSampler.h"

namespace sph {
namespace {

using bench::cameraAtFrame;
using bench::desc;
using bench::kAspect;

// --- The paper's claim in numbers: drops inside the view frustum (docs/benchmarks.md, "The
// paper's budgets along camera paths") ---

// Camera paths of 1 s at 30 fps from the still camera (0, 1, 4) looking along -z, fov 45:
// 0 still, 1 a 90-degree pan, 2 a dolly 3 m forward, 3 a zoom to fov 20.
scene::CameraDesc pathCamera(int path, int frame) {
  const double t = frame / 30.0;
  scene::CameraDesc c = cameraAtFrame(0);
  if (path == 1) c = cameraAtFrame(frame);
  if (path == 2) {
    c.position = Vec3(0, 1, static_cast<float>(4 - 3 * t));
    c.target = c.position - Vec3::UnitZ();
  }
  if (path == 3) c.fovYDegrees = static_cast<float>(45 - 25 * t);
  return c;
}

// The rain camera's frustum's volume near..far (a truncated pyramid), m^3.
double frustumVolume(const scene::CameraDesc& c, const scene::RainDesc& d) {
  const double t = std::tan(c.fovYDegrees * M_PI / 360);
  return 4.0 / 3.0 * t * t * kAspect * (std::pow(d.far, 3.0) - std::pow(d.near, 3.0));
}

// args: drops, spawn (0 view, 1 box, 2 region), path (pathCamera). One iteration = 30 frames of
// the path after a reset; counters: the minimum over the frames of the share of the budget in
// the frustum and of the drops in the frustum per m^3 of it.
void RainInView(benchmark::State& state) {
  const scene::RainDesc d = desc(state.range(0), state.range(1));
  const int path = static_cast<int>(state.range(2));
  double minShare = 1, minDensity = 1e30;
  for (auto _ : state) {
    rain::RainSystem r(d, kAspect);
    r.reset(pathCamera(path, 0));
    for (int f = 1; f <= 30; ++f) {
      const scene::CameraDesc c = pathCamera(path, f);
      r.update(c, 1.0f / 30);
      const std::size_t in = bench::dropsInFrustum(r, c, d);
      minShare = std::min(minShare, static_cast<double>(in) / static_cast<double>(r.size()));
      minDensity = std::min(minDensity, static_cast<double>(in) / frustumVolume(c, d));
    }
  }
  state.counters["min_in_view"] = minShare;
  state.counters["min_per_m3"] = minDensity;
}
BENCHMARK(RainInView)
    ->ArgsProduct({{1000, 10500, 49500}, {0, 1, 2}, {0, 1, 2, 3}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// --- The paper's Table 1: random number methods for spawning (docs/benchmarks.md, "The paper's
// Table 1: random numbers for spawning") ---

// args: method (0 rand(), 1 srand(seed) + rand(), 2 std::mt19937 + uniform_real_distribution,
// 3 ours: the counter-based hash, OpenMP), sampling (0 uniform: rejection from the sphere's
// cube, 1 the paper's eq. (7)). One iteration places 10^6 drops in the rain space of the still
// camera (sphere sample + side-plane test, eq. (5)-(9)); counters: chi-square of the sphere
// samples' radii ((r / R)^3 in 10 bins, 9 dof, 27.9 is p = 0.001) and directions (cos(phi) x theta
// in 10 x 10 bins, 99 dof, 148.2 is p = 0.001) against the uniform ball.
void RainSpawnRng(benchmark::State& state) {
  const int method = static_cast<int>(state.range(0));
  const auto sampling = static_cast<scene::RainSampling>(state.range(1));
  const rain::RainSpace space = rain::RainSpace::build(cameraAtFrame(0), kAspect, 0.1f, 5);
  constexpr std::size_t kSpawns = 1000000;
  std::vector<Vec3> ball;  // every sphere sample of the last iteration, unit ball
  std::uint64_t iteration = 0, candidates = 0;
  // The paper's serial generators; `record` keeps every sphere sample (outside the timing).
  // Uniform sampling as ours (sim/rain/ViewSampler.h): rejection from the cube, 3 numbers a
  // candidate.
  auto spawnSerial = [&](bool record) {
    std::mt19937 engine(2021);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    if (method == 1 || record) std::srand(static_cast<unsigned>(2021 + iteration));
    auto next = [&]() {
      if (method == 2) return uniform(engine);
      return static_cast<float>(std::rand()) / (static_cast<float>(RAND_MAX) + 1.0f);
    };
    auto ballPoint = [&]() {
      if (sampling == scene::RainSampling::Paper) {
        const float u[5] = {next(), next(), next(), next(), next()};
        return rain::paperBallPoint(u);
      }
      for (;;) {
        candidates += record;
        const float u[3] = {next(), next(), next()};
        const Vec3 q(2 * u[0] - 1, 2 * u[1] - 1, 2 * u[2] - 1);
        if (q.squaredNorm() <= 1) return q;
      }
    };
    std::vector<Vec3> placed(kSpawns);
    for (std::size_t i = 0; i < kSpawns; ++i) {
      for (;;) {
        const Vec3 b = ballPoint();
        if (record) ball.push_back(b);
        if (space.insideSides(space.centre + space.radius * b)) {
          placed[i] = b;
          break;
        }
      }
    }
    benchmark::DoNotOptimize(placed.data());
  };
  // Ours, `paper`: eq. (7) from the counter-based numbers, as RainSystem draws them.
  auto paperTry = [&](std::size_t i, std::uint64_t t) {
    float u[5];
    for (int j = 0; j < 5; ++j) u[j] = rain::unitRandom(2021 + iteration, i, 0, 8 * t + j);
    return rain::paperBallPoint(u);
  };
  const auto always = [](const Vec3&) { return true; };
  for (auto _ : state) {
    ball.clear();
    candidates = 0;
    ++iteration;
    if (method < 3) {
      spawnSerial(false);
    } else {
      std::vector<Vec3> placed(kSpawns);
      std::vector<std::uint32_t> tries(kSpawns);
      const auto n = static_cast<std::ptrdiff_t>(kSpawns);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t k = 0; k < n; ++k) {
        const auto i = static_cast<std::size_t>(k);
        if (sampling == scene::RainSampling::Uniform) {  // the shipped sampler
          rain::ViewSpawnCount count;
          rain::spawnInView(space, rain::DropRandom(2021 + iteration, i, 0), 1 << 20, always,
                            placed[i], count);
          tries[i] = static_cast<std::uint32_t>(count.rejected + count.outsideSphere);
          continue;
        }
        for (std::uint64_t t = 0;; ++t) {
          const Vec3 b = paperTry(i, t);
          if (space.insideSides(space.centre + space.radius * b)) {
            placed[i] = b, tries[i] = static_cast<std::uint32_t>(t);
            break;
          }
        }
      }
      benchmark::DoNotOptimize(placed.data());
      // The statistics below want every sample, rejected ones too: draw them again, serially,
      // after the timed part.
      state.PauseTiming();
      for (std::size_t i = 0; i < kSpawns; ++i) {
        const rain::DropRandom u(2021 + iteration, i, 0);
        for (std::uint64_t t = 0; t <= tries[i]; ++t) {
          if (sampling == scene::RainSampling::Paper) {
            ball.push_back(paperTry(i, t));
            continue;
          }
          ++candidates;
          const std::uint64_t hash = u.bits(1 + t);
          if (rain::viewCandidate(space, hash).inSphere) ball.push_back(rain::cubePoint(hash));
        }
      }
      state.ResumeTiming();
    }
  }
  if (method < 3) spawnSerial(true);
  std::vector<double> radial(10, 0), angular(100, 0);
  for (const Vec3& b : ball) {
    const double r = b.norm();
    radial[std::min(9, static_cast<int>(10 * r * r * r))] += 1;
    if (r <= 0) continue;
    const double cosPhi = std::clamp(b.z() / r, -1.0, 1.0);
    const double theta = std::atan2(b.y(), b.x()) + M_PI;
    const int i = std::min(9, static_cast<int>(5 * (cosPhi + 1)));
    const int j = std::min(9, static_cast<int>(10 * theta / (2 * M_PI)));
    angular[10 * i + j] += 1;
  }
  auto chiSquare = [](const std::vector<double>& bins) {
    double total = 0, chi = 0;
    for (double b : bins) total += b;
    const double expected = total / static_cast<double>(bins.size());
    for (double b : bins) chi += (b - expected) * (b - expected) / expected;
    return chi;
  };
  state.counters["chi2_radius"] = chiSquare(radial);
  state.counters["chi2_direction"] = chiSquare(angular);
  state.counters["samples_per_spawn"] =
      static_cast<double>(ball.size()) / static_cast<double>(kSpawns);
  // `uniform`: the cube's candidates (sphere samples and those outside the sphere)
  if (sampling == scene::RainSampling::Uniform)
    state.counters["candidates_per_spawn"] =
        static_cast<double>(candidates) / static_cast<double>(kSpawns);
  state.counters["spawns/s"] = benchmark::Counter(static_cast<double>(state.iterations() * kSpawns),
                                                  benchmark::Counter::kIsRate);
}
BENCHMARK(RainSpawnRng)
    ->ArgsProduct({{0, 1, 2, 3}, {0}})
    ->Args({2, 1})
    ->Args({3, 1})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sph
