// The distribution behind `rain.sampling` (docs/benchmarks.md, "The paper's Table 1"), once with
// our uniform ball sampling and once with eq. (7) read literally (a separate random radius per
// axis). Prints CSV for scripts/plot_rain_sampling.py, per sampling and bin: the density of the
// radius of 10^6 points of the sphere of eq. (5) (with the counter-based numbers, before the side
// planes: `uniform` the cube's points inside the ball as sim/rain/ViewSampler.h takes them, `paper`
// eq. (6)-(7); in sphere radii, the uniform ball is 3 r^2), and the density of the depth (distance
// from the camera along its axis, in units of `far`) of the 10^6 drops the shipped RainSystem
// spawns in the rain space of a still camera. With the argument `fov` (docs/rain.md, "How
// `uniform` places a drop"): per vertical field of view from 1 to 150 degrees, when 10^6 drops are
// spawned, the region the candidates came from (the sphere's cube or the frustum's pyramid),
// candidates per drop, the share accepted, the share the volumes predict (volume(frustum and
// sphere) / volume(region), RainSpace::volume, an independent Monte Carlo estimate), the share
// parked (RainCounters::parked), the wall time of the spawn, and the share `paper` sampling
// (eq. (7) from the whole sphere) parks, of 10^5 drops.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSystem.h"
#include "sim/rain/UnitBall.h"

namespace {

using namespace sph;
constexpr std::size_t kDrops = 1000000;
constexpr float kAspect = 960.0f / 540.0f;

scene::CameraDesc stillCamera(float fov) {  // bench_rain's: at (0, 1, 4) looking along -z
  scene::CameraDesc camera;
  camera.position = Vec3(0, 1, 4);
  camera.target = Vec3(0, 1, 3);
  camera.fovYDegrees = fov;
  return camera;
}

scene::RainDesc viewRain(scene::RainSampling sampling) {
  scene::RainDesc d;
  d.count = kDrops, d.near = 0.1f, d.far = 5, d.spawn = scene::RainSpawn::View,
  d.sampling = sampling;
  return d;
}

void acceptanceAgainstFov() {
  std::printf(
      "fov_deg,region,candidates_per_drop,accepted_share,predicted_share,parked_share,spawn_ms,"
      "paper_parked_share\n");
  for (const float fov : {1.f, 2.f, 3.f, 5.f, 8.f, 10.f, 20.f, 30.f, 35.f, 40.f, 45.f, 60.f, 75.f,
                          90.f, 105.f, 120.f, 150.f}) {
    rain::RainSystem rain(viewRain(scene::RainSampling::Uniform), kAspect);
    const auto start = std::chrono::steady_clock::now();
    rain.reset(stillCamera(fov));
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const rain::RainCounters& c = rain.counters();
    const double candidates = double(c.rejected + c.outsideSphere + c.accepted);
    const rain::RainSpace& s = rain.space();
    const bool pyramid = s.drawsFromPyramid();
    const double region = pyramid ? s.pyramidVolume() : 8.0 * std::pow(double(s.radius), 3.0);
    // eq. (7) from the whole sphere, as the paper places them: a tenth of the drops.
    scene::RainDesc paperDesc = viewRain(scene::RainSampling::Paper);
    paperDesc.count = kDrops / 10;
    rain::RainSystem paper(paperDesc, kAspect);
    paper.reset(stillCamera(fov));
    std::printf("%g,%s,%.4f,%.5f,%.5f,%.6f,%.1f,%.5f\n", fov, pyramid ? "pyramid" : "cube",
                candidates / double(kDrops), double(c.accepted) / candidates, s.volume() / region,
                double(c.parked) / double(kDrops), ms,
                double(paper.counters().parked) / double(paperDesc.count));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "fov") {
    acceptanceAgainstFov();
    return 0;
  }
  if (argc != 1) {
    std::fprintf(stderr, "usage: rain_sampling [fov]\n");
    return 2;
  }
  constexpr int kBins = 50;
  const scene::CameraDesc camera = stillCamera(45);  // 45 degrees, 16:9
  std::printf("sampling,bin_lo,bin_hi,radius_density,depth_density\n");
  for (const scene::RainSampling sampling :
       {scene::RainSampling::Uniform, scene::RainSampling::Paper}) {
    rain::RainSystem rain(viewRain(sampling), kAspect);
    rain.reset(camera);
    const rain::RainSpace& s = rain.space();
    std::vector<double> radius(kBins, 0), depth(kBins, 0);
    std::uint64_t draw = 0;
    for (std::size_t i = 0; i < kDrops; ++i) {
      const double r = rain::unitBallPoint(sampling, 7, i, draw).norm();
      radius[std::min(kBins - 1, static_cast<int>(r * kBins))] += 1;
    }
    for (const Vec3& p : rain.positions()) {
      const double z = (p - s.eye).dot(s.forward) / s.far;
      depth[std::min(kBins - 1, std::max(0, static_cast<int>(z * kBins)))] += 1;
    }
    for (int b = 0; b < kBins; ++b) {
      const double scale = kBins / static_cast<double>(kDrops);  // counts to a density per unit
      std::printf("%s,%g,%g,%.6g,%.6g\n", nameOf(sampling), b / double(kBins),
                  (b + 1) / double(kBins), radius[b] * scale, depth[b] * scale);
    }
  }
  return 0;
}
