// Points of the unit ball as the rain's two samplings draw them, from the counter-based numbers of
// a seed: for the statistics of docs/rain.md (the chi-square tests, bench/rain_sampling.cpp) -
// one function, so that the test and the plot measure the same points.
#pragma once

#include <cstdint>

#include "sim/scene/RainDesc.h"
#include "sim/Types.h"
#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSystem.h"
#include "sim/rain/ViewSampler.h"

namespace sph::rain {

// Point i of `seed`'s: `uniform` the next point of the cube (sim/rain/ViewSampler.h) inside the
// ball, from the hashes of draws `draw`, `draw` + 1, ... of drop 0 (`draw` is advanced past the
// ones taken); `paper` eq. (6)-(7) from draws 0-4 of drop i.
inline Vec3 unitBallPoint(scene::RainSampling sampling, std::uint64_t seed, std::uint64_t i,
                          std::uint64_t& draw) {
  if (sampling == scene::RainSampling::Uniform) {
    for (;;) {
      const Vec3 b = cubePoint(hash4(seed, 0, 0, draw++));
      if (b.squaredNorm() <= 1) return b;
    }
  }
  float u[5];
  for (std::uint64_t k = 0; k < 5; ++k) u[k] = unitRandom(seed, i, 0, k);
  return paperBallPoint(u);
}

}  // namespace sph::rain
