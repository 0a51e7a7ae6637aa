// The grid must find exactly the brute-force neighbour sets (STYLE.md rule 12), including points
// on cell borders, at negative coordinates and in grids that had to grow their cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "sim/grid/NeighbourGrid.h"

namespace sph {
namespace {

struct Cloud {
  std::vector<float> x, y, z;
  void add(float a, float b, float c) { x.push_back(a), y.push_back(b), z.push_back(c); }
};

std::vector<std::set<std::uint32_t>> bruteForce(const Cloud& c, float h) {
  const std::size_t n = c.x.size();
  std::vector<std::set<std::uint32_t>> out(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      if (grid::withinRadius(c.x[i] - c.x[j], c.y[i] - c.y[j], c.z[i] - c.z[j], h))
        out[i].insert(j);
  return out;
}

// Neighbour sets from the grid, mapped back to the original indices.
std::vector<std::set<std::uint32_t>> fromGrid(const Cloud& c, float h, std::size_t maxCells = 0) {
  grid::NeighbourGrid grid;
  std::vector<std::uint32_t> order;
  grid.build(c.x.data(), c.y.data(), c.z.data(), c.x.size(), h, order, maxCells);
  Cloud sorted;
  for (std::uint32_t o : order) sorted.add(c.x[o], c.y[o], c.z[o]);
  std::vector<std::set<std::uint32_t>> out(c.x.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    grid.forEachNeighbourRange(
        grid.cellOf(sorted.x[i], sorted.y[i], sorted.z[i]), [&](std::uint32_t b, std::uint32_t e) {
          for (std::uint32_t j = b; j < e; ++j) {
            if (grid::withinRadius(sorted.x[i] - sorted.x[j], sorted.y[i] - sorted.y[j],
                                   sorted.z[i] - sorted.z[j], h)) {
              out[order[i]].insert(order[j]);
            }
          }
        });
  }
  return out;
}

TEST(NeighbourGrid, MatchesBruteForceOnRandomPointsAroundTheOrigin) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.3f, 0.2f);  // straddles 0: negative cells too
  for (float h : {0.02f, 0.05f, 0.11f}) {
    Cloud c;
    for (int i = 0; i < 1500; ++i) c.add(u(rng), u(rng), u(rng));
    EXPECT_EQ(fromGrid(c, h), bruteForce(c, h)) << "h = " << h;
  }
}

TEST(NeighbourGrid, MatchesBruteForceOnCellBordersAndAtExactlyTheRadius) {
  // Points on the lattice of multiples of h lie exactly on cell borders; pairs one h apart are
  // exactly at the radius (not neighbours), pairs a float step closer are.
  const float h = 0.25f;  // exact in binary, so k*h is exact too
  Cloud c;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -2; k <= 2; ++k) c.add(i * h, j * h, k * h);
  c.add(std::nextafter(h, 0.0f), 0, 0);
  c.add(-std::nextafter(h, 0.0f), std::nextafter(0.0f, 1.0f), 0);
  c.add(0.5f * h, 0.5f * h, 0.5f * h);
  const auto expected = bruteForce(c, h);
  EXPECT_EQ(fromGrid(c, h), expected);
  // Sanity: the point at (h, 0, 0) is not a neighbour of the origin, (h - ulp, 0, 0) is.
  const std::size_t origin = static_cast<std::size_t>(3 * 35 + 3 * 5 + 2);
  ASSERT_EQ(c.x[origin], 0.0f);
  EXPECT_EQ(expected[origin].count(origin + 35), 0u);
  EXPECT_EQ(expected[origin].count(c.x.size() - 3), 1u);
}

TEST(NeighbourGrid, StaysExactWhenTheBoxForcesLargerCells) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  Cloud c;
  for (int i = 0; i < 800; ++i) c.add(u(rng), u(rng) * 0.01f, u(rng));
  c.add(1000.0f, 0, 0);  // an outlier far away: the box becomes huge
  grid::NeighbourGrid g;
  std::vector<std::uint32_t> order;
  g.build(c.x.data(), c.y.data(), c.z.data(), c.x.size(), 0.3f, order, 4096);
  EXPECT_GT(g.cellSize(), 0.3f);
  EXPECT_LE(g.cellCount(), 4096u);
  EXPECT_EQ(fromGrid(c, 0.3f, 4096), bruteForce(c, 0.3f));
}

TEST(NeighbourGrid, CountingSortIsAStablePermutationByCell) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Cloud c;
  for (int i = 0; i < 5000; ++i) c.add(u(rng), u(rng), u(rng));
  grid::NeighbourGrid g;
  std::vector<std::uint32_t> order;
  g.build(c.x.data(), c.y.data(), c.z.data(), c.x.size(), 0.1f, order);
  std::vector<std::uint32_t> sorted(order);
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
  // Cells never decrease along the order; inside a cell the original order is kept.
  auto key = [&](std::uint32_t i) {
    const grid::CellCoord cc = g.cellOf(c.x[i], c.y[i], c.z[i]);
    return std::make_tuple(cc[2], cc[1], cc[0]);
  };
  for (std::size_t i = 1; i < order.size(); ++i) {
    ASSERT_LE(key(order[i - 1]), key(order[i]));
    if (key(order[i - 1]) == key(order[i])) {
      ASSERT_LT(order[i - 1], order[i]);
    }
  }
  EXPECT_EQ(g.pointCount(), c.x.size());
}

}  // namespace
}  // namespace sph
