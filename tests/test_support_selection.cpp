// The DFSPH factor pass's selection of the candidates inside the support
// (sim/grid/SupportSelection.h): the scalar version - what a build without AVX-512 runs - and the
// AVX-512 one keep exactly the candidates with 0 < r^2 < h^2, in their order, with their offsets,
// r^2 and index bits, and pad the selection with zeros. Both are compiled and compared here
// whenever the build's CPU has AVX-512, so the fallback is tested on a machine that would never
// run it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "sim/grid/SupportSelection.h"

namespace sph {
namespace {

constexpr float kH = 0.04f;

// A cell's batch as the factor pass sees it: `count` candidates around the particle at `centre`
// (the particle itself among them), padded to kBatchLanes with far-away points, and index bits
// that are not numbers (NaN patterns and denormals among them).
struct Batch {
  grid::CandidateBatch<4> b;
  float centre[3] = {0.31f, -1.2f, 0.05f};
};

Batch randomBatch(std::size_t count, std::mt19937& rng) {
  Batch t;
  std::uniform_real_distribution<float> offset(-2 * kH, 2 * kH);
  std::uniform_int_distribution<std::uint32_t> id;
  t.b.clear();
  t.b.resize(count + grid::kBatchLanes);
  std::uniform_int_distribution<std::size_t> self(0, count ? count - 1 : 0);
  const std::size_t selfAt = self(rng);
  for (std::size_t j = 0; j < count; ++j) {
    float d[3];
    double r2;
    do {  // not within rounding of the support's edge, where the two versions' r^2 may differ
      for (float& v : d) v = offset(rng);
      r2 = double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2];
    } while (std::fabs(r2 - double(kH) * kH) < 1e-4 * kH * kH);
    for (int a = 0; a < 3; ++a) t.b.field[a][j] = j == selfAt ? t.centre[a] : t.centre[a] + d[a];
    const std::uint32_t bits = j % 5 == 0 ? 0x7fc00000u + j : j % 5 == 1 ? j : id(rng);
    std::memcpy(&t.b.field[3][j], &bits, sizeof bits);
  }
  t.b.count = count;
  t.b.pad();
  return t;
}

struct Selected {
  std::vector<std::uint32_t> bits;
  std::vector<float> dx, dy, dz, r2;
  std::size_t padded = 0;
};

// What the pass needs, computed plainly.
Selected reference(const Batch& t) {
  Selected s;
  for (std::size_t j = 0; j < t.b.padded; ++j) {
    const float dx = t.centre[0] - t.b.field[0][j], dy = t.centre[1] - t.b.field[1][j],
                dz = t.centre[2] - t.b.field[2][j];
    const double r2 = double(dx) * dx + double(dy) * dy + double(dz) * dz;
    if (!(r2 > 0 && r2 < double(kH) * kH)) continue;
    std::uint32_t bits;
    std::memcpy(&bits, &t.b.field[3][j], sizeof bits);
    s.bits.push_back(bits), s.dx.push_back(dx), s.dy.push_back(dy), s.dz.push_back(dz);
    s.r2.push_back(static_cast<float>(r2));
  }
  return s;
}

void expectSelected(const Selected& expected, std::size_t count, const grid::SupportSelection& out,
                    const char* which) {
  ASSERT_EQ(expected.bits.size(), count) << which;
  ASSERT_EQ(out.count, count) << which;
  ASSERT_EQ(out.padded % grid::kBatchLanes, 0u) << which;
  ASSERT_GE(out.padded, count) << which;
  ASSERT_LT(out.padded, count + grid::kBatchLanes) << which;
  for (std::size_t q = 0; q < count; ++q) {
    std::uint32_t bits;
    std::memcpy(&bits, &out.field[4][q], sizeof bits);
    ASSERT_EQ(expected.bits[q], bits) << which << " candidate " << q;
    ASSERT_EQ(expected.dx[q], out.field[0][q]) << which << " candidate " << q;
    ASSERT_EQ(expected.dy[q], out.field[1][q]) << which << " candidate " << q;
    ASSERT_EQ(expected.dz[q], out.field[2][q]) << which << " candidate " << q;
    ASSERT_NEAR(expected.r2[q], out.field[3][q], 1e-6f * kH * kH) << which << " candidate " << q;
  }
  for (std::size_t q = count; q < out.padded; ++q) {  // padding: +0 bits, outside, adds nothing
    for (int f = 0; f < 5; ++f) {
      std::uint32_t bits;
      std::memcpy(&bits, &out.field[f][q], sizeof bits);
      ASSERT_EQ(bits, 0u) << which << " padding " << q << " of field " << f;
    }
  }
}

template <class Select>
void checkVersion(const Batch& t, const Selected& expected, Select&& select, const char* which) {
  grid::SupportSelection out;
  out.resize(t.b.padded);
  for (auto& f : out.field) std::fill(f.begin(), f.end(), -7.0f);  // no help from a clean buffer
  const std::size_t count =
      select(t.centre[0], t.centre[1], t.centre[2], kH * kH, t.b.padded, t.b.field[0].data(),
             t.b.field[1].data(), t.b.field[2].data(), t.b.field[3].data(), out);
  expectSelected(expected, count, out, which);
}

TEST(SupportSelection, BothVersionsKeepTheCandidatesInsideTheSupportInTheirOrder) {
  std::mt19937 rng(2017);
  [[maybe_unused]] int withAvx512 = 0;  // counted only where the AVX-512 version is built
  for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{15}, std::size_t{16},
                            std::size_t{57}, std::size_t{216}}) {
    for (int round = 0; round < 100; ++round) {
      const Batch t = randomBatch(count, rng);
      const Selected expected = reference(t);
      checkVersion(t, expected, grid::selectInsideScalar, "scalar");
      checkVersion(t, expected, grid::selectInside, "the build's choice");
#if SPHSPLAT_SELECT_SUPPORT_AVX512
      checkVersion(t, expected, grid::selectInsideAvx512, "AVX-512");
      ++withAvx512;
#endif
    }
  }
#if SPHSPLAT_SELECT_SUPPORT_AVX512
  EXPECT_EQ(withAvx512, 600);
#else
  GTEST_LOG_(INFO) << "built without AVX-512: the scalar version alone was compared";
#endif
}

// A candidate at the particle's own place (r = 0) is never its neighbour, nor is one exactly on
// the support's edge; one just inside it is. Every version built here.
template <class Select>
void checkEdges(Select&& select, const char* which) {
  grid::CandidateBatch<4> b;
  b.resize(grid::kBatchLanes);
  const float at[4] = {0.0f, kH, 0.5f * kH, std::nextafter(kH, 0.0f)};
  for (int j = 0; j < 4; ++j) {
    b.field[0][j] = at[j], b.field[1][j] = 0, b.field[2][j] = 0;
    const std::uint32_t bits = 100u + j;
    std::memcpy(&b.field[3][j], &bits, sizeof bits);
  }
  b.count = 4;
  b.pad();
  grid::SupportSelection out;
  out.resize(b.padded);
  const std::size_t count = select(0, 0, 0, kH * kH, b.padded, b.field[0].data(), b.field[1].data(),
                                   b.field[2].data(), b.field[3].data(), out);
  ASSERT_EQ(count, 2u) << which;
  std::uint32_t bits[2];
  std::memcpy(bits, out.field[4].data(), sizeof bits);
  EXPECT_EQ(bits[0], 102u) << which;
  EXPECT_EQ(bits[1], 103u) << which;
  EXPECT_EQ(out.field[0][0], -0.5f * kH) << which;
}

TEST(SupportSelection, LeavesOutTheParticleItselfAndTheEdge) {
  checkEdges(grid::selectInsideScalar, "scalar");
  checkEdges(grid::selectInside, "the build's choice");
#if SPHSPLAT_SELECT_SUPPORT_AVX512
  checkEdges(grid::selectInsideAvx512, "AVX-512");
#endif
}

}  // namespace
}  // namespace sph
