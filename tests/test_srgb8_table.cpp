// render/frame/Srgb8Table: the 8-bit sRGB code by table is toSrgb8's (Lighting.h: clamp, encode,
// round), but where a value lies within float rounding of a code's threshold - and there one step
// apart at most, as GL's own pow() may land either side.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "render/frame/Lighting.h"
#include "render/frame/Srgb8Table.h"

namespace sph::render::frame {
namespace {

TEST(Srgb8Table, IsTheEncodingOfToSrgb8) {
  const Srgb8Table& table = srgb8Table();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::size_t differ = 0;
  int worst = 0;
  const std::size_t n = 1000000;
  for (std::size_t i = 0; i < n; ++i) {
    // Uniform and, for the dark codes where the linear segment ends, uniform in the log.
    const float c = i % 2 ? u(rng) : std::pow(10.0f, -6.0f * u(rng));
    const int d = std::abs(int(table(c)) - int(toSrgb8(c)));
    worst = std::max(worst, d), differ += d != 0;
  }
  EXPECT_LE(worst, 1);
  EXPECT_LT(differ, n / 10000) << "only next to a threshold";
  // Every code's own value (its centre) and both ends.
  for (int k = 0; k < 256; ++k) {
    const float e = k / 255.0f;
    const float c = e <= 0.04045f ? e / 12.92f : std::pow((e + 0.055f) / 1.055f, 2.4f);
    EXPECT_EQ(table(c), k) << k;
  }
  EXPECT_EQ(table(-1.0f), 0);
  EXPECT_EQ(table(2.0f), 255);
  EXPECT_EQ(table(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(table(std::numeric_limits<float>::infinity()), 255);
}

}  // namespace
}  // namespace sph::render::frame
