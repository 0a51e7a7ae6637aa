// Particles::permute() and assignFrom() must move every field together (STYLE.md rule 3). A
// field missing from Particles::fields() fails the static_assert in Particles.h; these tests
// check the listed ones move.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>

#include "sim/Particles.h"

namespace sph {
namespace {

// n particles with ids 0..n-1 whose field f holds a value unique to (f, id).
Particles uniquelyFilled(std::size_t n) {
  Particles p;
  p.resize(n);
  int field = 0;
  for (std::size_t i = 0; i < n; ++i) p.id[i] = static_cast<std::uint32_t>(i);
  p.forEachField([&](auto& values) {
    ++field;
    if (static_cast<void*>(&values) == static_cast<void*>(&p.id)) return;
    for (std::size_t i = 0; i < n; ++i) {
      const float v = static_cast<float>(field * 100000 + i);
      std::memcpy(&values[i], &v, 4);
    }
  });
  EXPECT_EQ(field, Particles::kFieldCount);
  return p;
}

// Every field of every slot still holds the value of the particle whose id is there.
void expectFieldsFollowTheirIds(const Particles& p) {
  int field = 0;
  p.forEachField([&](const auto& values) {
    ++field;
    ASSERT_EQ(values.size(), p.size());
    if (static_cast<const void*>(&values) == static_cast<const void*>(&p.id)) return;
    for (std::size_t i = 0; i < p.size(); ++i) {
      float v;
      std::memcpy(&v, &values[i], 4);
      ASSERT_EQ(v, static_cast<float>(field * 100000 + p.id[i]))
          << "field " << field << " slot " << i;
    }
  });
}

TEST(Particles, PermuteMovesEveryFieldWithItsParticle) {
  const std::size_t n = 1000;
  Particles p = uniquelyFilled(n);
  std::vector<std::uint32_t> order(n), scratch;
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  p.permute(order, scratch);
  expectFieldsFollowTheirIds(p);
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(p.id[i], order[i]);
}

TEST(Particles, AssignFromTakesEveryFieldOfTheChosenParticles) {
  const Particles all = uniquelyFilled(1000);
  std::vector<std::uint32_t> at;  // every third, backwards (a rank's share of a gathered fluid)
  for (std::uint32_t i = 999; i >= 3; i -= 3) at.push_back(i);
  Particles mine = uniquelyFilled(7);  // what was there is replaced, size included
  mine.assignFrom(all, at);
  ASSERT_EQ(mine.size(), at.size());
  expectFieldsFollowTheirIds(mine);
  for (std::size_t i = 0; i < at.size(); ++i) EXPECT_EQ(mine.id[i], at[i]);
}

TEST(Particles, AppendFillsEveryField) {
  Particles p;
  p.append(Vec3(1, 2, 3), Vec3(4, 5, 6), 42, 1000.0f);
  p.forEachField([](const auto& values) { EXPECT_EQ(values.size(), 1u); });
  EXPECT_EQ(p.position(0), Vec3(1, 2, 3));
  EXPECT_EQ(p.velocity(0), Vec3(4, 5, 6));
  EXPECT_EQ(p.rho[0], 1000.0f);
  EXPECT_EQ(p.id[0], 42u);
  EXPECT_LT(p.collideTime[0], 0.0f);  // free to collide at once
}

}  // namespace
}  // namespace sph
