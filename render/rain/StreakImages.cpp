#include "render/rain/StreakImages.h"

#include <algorithm>
#include <cmath>

#include "sim/rain/RainRandom.h"

namespace sph::render::rain {

StreakImages generateStreakImages(int layers, int width, int height, std::uint64_t seed) {
  StreakImages s;
  s.width = width, s.height = height, s.layers = layers;
  s.alpha.resize(static_cast<std::size_t>(layers) * width * height);
  for (int l = 0; l < layers; ++l) {
    auto u = [&](std::uint64_t draw) {
      return sph::rain::unitRandom(seed, 0xa11a, static_cast<std::uint64_t>(l), draw);
    };
    const float sigma = 0.12f + 0.12f * u(0);  // core width, fraction of the image width
    const float ripples = 1.0f + 4.0f * u(1);  // oscillation periods along the streak
    const float ripple = 0.15f + 0.3f * u(2);  // their depth
    const float phase = 2 * static_cast<float>(M_PI) * u(3);
    const float fade = 0.1f + 0.2f * u(4);    // length fraction of each fading end
    const float peak = 0.55f + 0.45f * u(5);  // brightest alpha
    for (int row = 0; row < height; ++row) {
      const float t = (static_cast<float>(row) + 0.5f) / static_cast<float>(height);
      const float ends = std::clamp(std::min(t, 1 - t) / fade, 0.0f, 1.0f);
      const float along =
          ends *
          (1 - ripple * 0.5f * (1 + std::sin(2 * static_cast<float>(M_PI) * ripples * t + phase)));
      for (int column = 0; column < width; ++column) {
        const float x = (static_cast<float>(column) + 0.5f) / static_cast<float>(width) - 0.5f;
        const float across = std::exp(-0.5f * (x / sigma) * (x / sigma));
        const float a = std::clamp(peak * along * across, 0.0f, 1.0f);
        s.alpha[(static_cast<std::size_t>(l) * height + row) * width + column] =
            static_cast<std::uint8_t>(std::lround(255.0f * a));
      }
    }
  }
  return s;
}

}  // namespace sph::render::rain
