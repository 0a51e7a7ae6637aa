// The DFSPH factor pass's pair packing (sim/grid/PairPacking.h): the scalar version - what a build
// without AVX-512 runs - and the AVX-512 one keep exactly the candidates with h - r > 0, with
// their index bits and values, in their order. Both are compiled and compared here whenever the
// build's CPU has AVX-512, so the fallback is tested on a machine that would never run it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "sim/grid/PairPacking.h"

namespace sph {
namespace {

struct Packed {
  std::vector<std::uint32_t> index;
  std::vector<float> gx, gy, gz, hr;
  std::uint32_t count = 0;

  explicit Packed(std::size_t room)
      : index(room, 0xdeadbeefu), gx(room, -1), gy(room, -1), gz(room, -1), hr(room, -1) {}
  grid::PairRow row() { return {index.data(), gx.data(), gy.data(), gz.data(), hr.data()}; }
};

// A batch of `padded` candidates, about a third of them outside the support (h - r <= 0, among
// them 0, -0 and NaN, which no comparison calls inside), and index bits in `bits`.
grid::CandidateBatch<4> randomBatch(std::size_t padded, std::mt19937& rng,
                                    std::vector<float>& bits) {
  grid::CandidateBatch<4> t;
  t.resize(padded);
  t.count = t.padded = padded;
  std::uniform_real_distribution<float> value(-1, 1);
  std::uniform_int_distribution<int> kind(0, 8);
  bits.resize(padded);
  for (std::size_t j = 0; j < padded; ++j) {
    for (int f = 0; f < 3; ++f) t.field[f][j] = value(rng);
    const int k = kind(rng);
    t.field[3][j] = k == 0   ? 0.0f
                    : k == 1 ? -0.0f
                    : k == 2 ? std::numeric_limits<float>::quiet_NaN()
                             : (k < 6 ? 1.0f : -1.0f) * (0.001f + std::fabs(value(rng)));
    const std::uint32_t id = static_cast<std::uint32_t>(rng());
    std::memcpy(&bits[j], &id, sizeof id);
  }
  return t;
}

// What the pass needs: the candidates inside, in order.
Packed reference(const std::vector<float>& bits, const grid::CandidateBatch<4>& t) {
  Packed p(t.padded);
  for (std::size_t j = 0; j < t.padded; ++j) {
    if (!(t.field[3][j] > 0.0f)) continue;
    std::memcpy(&p.index[p.count], &bits[j], sizeof(std::uint32_t));
    p.gx[p.count] = t.field[0][j], p.gy[p.count] = t.field[1][j];
    p.gz[p.count] = t.field[2][j], p.hr[p.count] = t.field[3][j];
    ++p.count;
  }
  return p;
}

void expectSamePairs(const Packed& expected, const Packed& actual, const char* which) {
  ASSERT_EQ(expected.count, actual.count) << which;
  for (std::uint32_t q = 0; q < expected.count; ++q) {
    ASSERT_EQ(expected.index[q], actual.index[q]) << which << " pair " << q;
    ASSERT_EQ(0, std::memcmp(&expected.gx[q], &actual.gx[q], 4)) << which << " pair " << q;
    ASSERT_EQ(0, std::memcmp(&expected.gy[q], &actual.gy[q], 4)) << which << " pair " << q;
    ASSERT_EQ(0, std::memcmp(&expected.gz[q], &actual.gz[q], 4)) << which << " pair " << q;
    ASSERT_EQ(0, std::memcmp(&expected.hr[q], &actual.hr[q], 4)) << which << " pair " << q;
  }
}

TEST(PairPacking, BothVersionsKeepTheCandidatesInsideTheSupportInTheirOrder) {
  std::mt19937 rng(2015);
  [[maybe_unused]] int withAvx512 = 0;  // counted only where the AVX-512 version is built
  for (std::size_t padded :
       {std::size_t{0}, grid::kBatchLanes, 2 * grid::kBatchLanes, 7 * grid::kBatchLanes}) {
    for (int round = 0; round < 200; ++round) {
      std::vector<float> bits;
      const grid::CandidateBatch<4> t = randomBatch(padded, rng, bits);
      const Packed expected = reference(bits, t);
      Packed scalar(padded);
      scalar.count = packPairsScalar(padded, bits.data(), t, scalar.row());
      expectSamePairs(expected, scalar, "scalar");
      Packed chosen(padded);
      chosen.count = packPairs(padded, bits.data(), t, chosen.row());
      expectSamePairs(expected, chosen, "the build's choice");
#if SPHSPLAT_PACK_PAIRS_AVX512
      Packed vector(padded);
      vector.count = packPairsAvx512(padded, bits.data(), t, vector.row());
      expectSamePairs(expected, vector, "AVX-512");
      ++withAvx512;
#endif
    }
  }
#if SPHSPLAT_PACK_PAIRS_AVX512
  EXPECT_EQ(withAvx512, 800);
#else
  GTEST_LOG_(INFO) << "built without AVX-512: the scalar version alone was compared";
#endif
}

}  // namespace
}  // namespace sph
