// Streak images for the rain's array texture (seed 002 section 3.3). The paper loads Garg &
// Nayar's rain streak database (Garg & Nayar 2006), which cannot be downloaded here: these are
// generated procedurally instead (docs/rain.md) - a bright core across the width (Gaussian), ends
// that fade in and out along the length, and a per-image brightness ripple along the streak like
// the oscillating drops of the database. CPU only, so they are tested without GL.
#pragma once

#include <cstdint>
#include <vector>

namespace sph::render::rain {

struct StreakImages {
  int width = 0, height = 0, layers = 0;  // pixels across, along, images
  std::vector<std::uint8_t> alpha;        // layer-major, then row (along), then column (across)
  std::uint8_t at(int layer, int row, int column) const {
    return alpha[(static_cast<std::size_t>(layer) * height + row) * width + column];
  }
};

// `layers` images of width x height, different per layer and a pure function of `seed`.
StreakImages generateStreakImages(int layers, int width, int height, std::uint64_t seed);

}  // namespace sph::render::rain
