// The distribution behind `rain.sampling` (issue 13, "Measured 3"; docs/benchmarks.md, "The
// paper's Table 1"), once with our uniform ball sampling and once with eq. (7) read literally (a
// separate random radius per axis). Prints CSV for scripts/plot_rain_sampling.py, per sampling
// and bin: the density of the radius of 10^6 points of the sphere of eq. (5) (sampleBall with
// the counter-based numbers, before the side planes; in sphere radii, the uniform ball is
// 3 r^2), and the density of the depth (distance from the camera along its axis, in units of
// `far`) of the 10^6 drops the shipped RainSystem spawns in the rain space of a still camera.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSystem.h"

int main() {
  using namespace sph;
  constexpr int kBins = 50;
  constexpr std::size_t kDrops = 1000000;
  CameraDesc camera;  // the still camera of bench_rain: 45 degrees, 16:9
  camera.position = Vec3(0, 1, 4);
  camera.target = Vec3(0, 1, 3);
  camera.fovYDegrees = 45;
  std::printf("sampling,bin_lo,bin_hi,radius_density,depth_density\n");
  for (const RainSampling sampling : {RainSampling::Uniform, RainSampling::Paper}) {
    RainDesc d;
    d.count = kDrops, d.near = 0.1f, d.far = 5, d.spawn = RainSpawn::View, d.sampling = sampling;
    rain::RainSystem rain(d, 960.0f / 540.0f);
    rain.reset(camera);
    const rain::RainSpace& s = rain.space();
    std::vector<double> radius(kBins, 0), depth(kBins, 0);
    for (std::size_t i = 0; i < kDrops; ++i) {
      float u[5];
      for (int j = 0; j < 5; ++j) u[j] = rain::unitRandom(7, i, 0, static_cast<std::uint64_t>(j));
      const double r = rain::sampleBall(sampling, u).norm();
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
