// The candidate cull of the cell-batched neighbour loops (sim/grid/CellBatch.h,
// appendNearCandidates()): the scalar version - what a build without AVX-512 runs - and the
// AVX-512 one keep exactly the candidates within sqrt(reach2) of the cell's box (and those whose
// distance is NaN), with all their fields, in their order, for ranges of every length, and write
// nothing past the room they are given. Both are compiled and compared here whenever the build's
// CPU has AVX-512, so the fallback is tested on a machine that would never run it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "sim/grid/CellBatch.h"

namespace sph {
namespace {

constexpr float kSentinel = -12345.0f;
constexpr std::size_t kGuard = 16;  // values past the room, which must stay untouched

struct Candidates {
  std::array<std::vector<float>, 4> field;  // x, y, z, index bits
};

// `n` candidates around the box [lo, hi]: about half within `reach` of it, a few with a NaN
// coordinate, none within 1e-4 of the bound in relative distance (a tie two roundings of the same
// distance may call either way).
Candidates randomCandidates(std::size_t n, const float lo[3], const float hi[3], float reach,
                            std::mt19937& rng) {
  Candidates c;
  std::uniform_real_distribution<float> along(-2.0f * reach, 2.0f * reach);
  std::uniform_int_distribution<int> kind(0, 40);
  for (std::size_t q = 0; q < n; ++q) {
    float p[3];
    while (true) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        p[a] = 0.5f * (lo[a] + hi[a]) + along(rng);
        const double d = std::max({double(lo[a]) - p[a], double(p[a]) - hi[a], 0.0});
        d2 += d * d;
      }
      if (std::abs(d2 / (double(reach) * reach) - 1.0) > 1e-4) break;
    }
    if (kind(rng) == 0) p[kind(rng) % 3] = std::numeric_limits<float>::quiet_NaN();
    for (int a = 0; a < 3; ++a) c.field[a].push_back(p[a]);
    const std::uint32_t id = static_cast<std::uint32_t>(rng());
    float bits;
    std::memcpy(&bits, &id, sizeof bits);
    c.field[3].push_back(bits);
  }
  return c;
}

// What the cull must keep, in double precision: a NaN distance is kept, as the scalar test does.
std::vector<std::size_t> reference(const Candidates& c, std::size_t begin, std::size_t end,
                                   const float lo[3], const float hi[3], float reach) {
  std::vector<std::size_t> kept;
  for (std::size_t q = begin; q < end; ++q) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double v = c.field[a][q];
      const double d = std::max(std::max(lo[a] - v, v - hi[a]), 0.0);
      d2 += d * d;
    }
    if (!(d2 >= double(reach) * reach)) kept.push_back(q);
  }
  return kept;
}

using Cull = std::size_t (*)(const std::array<const float*, 4>&, std::uint32_t, std::uint32_t,
                             const float[3], const float[3], float, const std::array<float*, 4>&);

void expectCull(Cull cull, const char* which, const Candidates& c, std::uint32_t begin,
                std::uint32_t end, const float lo[3], const float hi[3], float reach) {
  const std::size_t room = end - begin + 8;
  std::array<std::vector<float>, 4> out;
  std::array<float*, 4> to;
  for (int f = 0; f < 4; ++f) out[f].assign(room + kGuard, kSentinel), to[f] = out[f].data();
  const std::array<const float*, 4> src = {c.field[0].data(), c.field[1].data(), c.field[2].data(),
                                           c.field[3].data()};
  const std::size_t count = cull(src, begin, end, lo, hi, reach * reach, to);
  const std::vector<std::size_t> kept = reference(c, begin, end, lo, hi, reach);
  ASSERT_EQ(count, kept.size()) << which << ", range [" << begin << ", " << end << ")";
  for (std::size_t k = 0; k < kept.size(); ++k) {
    for (int f = 0; f < 4; ++f) {
      ASSERT_EQ(0, std::memcmp(&out[f][k], &c.field[f][kept[k]], sizeof(float)))
          << which << ": candidate " << k << ", field " << f;
    }
  }
  for (int f = 0; f < 4; ++f) {
    for (std::size_t k = room; k < room + kGuard; ++k)
      ASSERT_EQ(out[f][k], kSentinel) << which << " wrote past its room, field " << f;
  }
}

TEST(AppendNear, BothVersionsKeepTheCandidatesWithinReachInTheirOrder) {
  std::mt19937 rng(2026);
  const float lo[3] = {0.10f, -0.30f, 1.00f}, hi[3] = {0.13f, -0.27f, 1.04f};
  const float reach = 0.04f * 1.0001f;
  [[maybe_unused]] int withAvx512 = 0;  // counted only where the AVX-512 version is built
  for (int round = 0; round < 300; ++round) {
    const Candidates c = randomCandidates(64, lo, hi, reach, rng);
    // Ranges of every length from 0 to 40 (partial vectors of every width), at every offset.
    const auto begin = static_cast<std::uint32_t>(round % 17);
    const auto end = static_cast<std::uint32_t>(begin + round % 41);
    expectCull(&grid::appendNearScalar<4>, "scalar", c, begin, end, lo, hi, reach);
    expectCull(&grid::appendNearCandidates<4>, "the build's choice", c, begin, end, lo, hi, reach);
#if SPHSPLAT_APPEND_NEAR_AVX512
    expectCull(&grid::appendNearAvx512<4>, "AVX-512", c, begin, end, lo, hi, reach);
    ++withAvx512;
#endif
  }
#if SPHSPLAT_APPEND_NEAR_AVX512
  EXPECT_EQ(withAvx512, 300);
#else
  GTEST_LOG_(INFO) << "built without AVX-512: the scalar version alone was compared";
#endif
}

}  // namespace
}  // namespace sph
