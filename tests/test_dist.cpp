// The MPI-free pieces of the distributed run (docs/scaling.md): the slab cut covers every plane
// exactly once and balances the particle counts; the exact sum is exact and independent of the
// order and split of its terms (what makes the gradient correction the same on any number of
// ranks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "sim/dist/ExactSum.h"
#include "sim/dist/Halo.h"

namespace sph::dist {
namespace {

TEST(Slabs, EveryPlaneHasExactlyOneOwnerAndTheSlabsAreContiguous) {
  std::mt19937 rng(7);
  for (int ranks = 1; ranks <= 7; ++ranks) {
    std::vector<std::int64_t> counts(40);
    for (auto& c : counts) c = static_cast<std::int64_t>(rng() % 50);
    const Slabs s = Slabs::balance(1, ranks, -10, counts);
    ASSERT_EQ(s.ranks(), ranks);
    int previous = 0;
    for (long long p = -100; p < 100; ++p) {  // beyond the counted planes too
      const int owner = s.ownerOf(p);
      ASSERT_GE(owner, 0);
      ASSERT_LT(owner, ranks);
      ASSERT_GE(owner, previous) << "plane " << p;  // owners never go back: slabs
      EXPECT_TRUE(p >= s.first[owner] && p < s.first[owner + 1]) << "plane " << p;
      previous = owner;
    }
  }
}

TEST(Slabs, TheCutBalancesTheParticleCountsWithinOnePlane) {
  std::vector<std::int64_t> counts(100, 10);  // 1000 particles, 10 per plane
  const Slabs s = Slabs::balance(0, 4, 0, counts);
  for (int r = 0; r < 4; ++r) {
    std::int64_t n = 0;
    for (long long p = 0; p < 100; ++p) n += s.ownerOf(p) == r ? counts[p] : 0;
    EXPECT_NEAR(static_cast<double>(n), 250.0, 10.0) << "rank " << r;
  }
  // Water only in planes 30-39 (a pour's first layers): every rank still gets a share.
  std::vector<std::int64_t> lump(100, 0);
  for (int p = 30; p < 40; ++p) lump[p] = 100;
  const Slabs t = Slabs::balance(0, 2, 0, lump);
  EXPECT_EQ(t.first[1], 35);
  // No particles at all: equal slices of the planes.
  const Slabs u = Slabs::balance(0, 4, 0, std::vector<std::int64_t>(100, 0));
  EXPECT_EQ(u.first[1], 25);
  EXPECT_EQ(u.first[3], 75);
}

TEST(ExactSum, IsExactAndIndependentOfOrderAndSplit) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> mantissa(0.5f, 1.0f);
  std::vector<float> terms;
  for (int i = 0; i < 20000; ++i) {
    const int exponent = static_cast<int>(rng() % 60) - 30;
    const float sign = rng() % 3 == 0 ? -1.0f : 1.0f;
    terms.push_back(sign * std::ldexp(mantissa(rng), exponent));
  }
  terms.push_back(1e30f), terms.push_back(-1e30f), terms.push_back(1e-40f);  // huge, denormal
  ExactSum forward;
  for (float t : terms) forward.add(t);
  // Reversed, shuffled and split in three "ranks" whose digits are added: the same double.
  ExactSum reversed;
  for (auto it = terms.rbegin(); it != terms.rend(); ++it) reversed.add(*it);
  std::shuffle(terms.begin(), terms.end(), rng);
  ExactSum parts[3];
  for (std::size_t i = 0; i < terms.size(); ++i) parts[i % 3].add(terms[i]);
  ExactSum merged;
  for (ExactSum& p : parts) {
    p.normalise();
    merged.merge(p.digits());
  }
  EXPECT_EQ(forward.toDouble(), reversed.toDouble());
  EXPECT_EQ(forward.toDouble(), merged.toDouble());
  // Exact: a sum whose float terms cancel to a tiny remainder keeps it (double would not).
  ExactSum cancel;
  cancel.add(1e20f), cancel.add(3.0f), cancel.add(-1e20f);
  EXPECT_EQ(cancel.toDouble(), 3.0);
  // And close to a long-double sum in general.
  long double reference = 0;
  for (float t : terms) reference += std::abs(t) == 1e30f ? 0.0f : t;  // they cancel exactly
  EXPECT_NEAR(forward.toDouble(), static_cast<double>(reference),
              1e-12 * std::abs(static_cast<double>(reference)) + 1e-30);
}

}  // namespace
}  // namespace sph::dist
