// The MPI-free pieces of the distributed run (docs/scaling.md): the slab cut covers every plane
// exactly once and balances the particle counts; the exact sum is exact and independent of the
// order and split of its terms (what makes the gradient correction the same on any number of
// ranks). With K ranks as threads (tests/ThreadRanks.h): after each exchange the owned particles
// are every particle exactly once, in its owner's slab, and each rank's ghosts are exactly the
// particles a brute-force search finds across its faces, covering every neighbour pair within the
// support radius that the density and force passes use.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include <omp.h>

#include "sim/grid/NeighbourGrid.h"
#include "sim/ranks/ExactSum.h"
#include "sim/ranks/Halo.h"
#include "tests/HaloCloud.h"
#include "tests/ThreadRanks.h"

namespace sph::ranks {
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

TEST(ExactSum, AddAllIsAddOneByOne) {
  // addAll() (DFSPH's error means, sim/solver/Dfsph.cpp) sums by exponent first: the same exact sum,
  // digit for digit once normalised, over every exponent (subnormals, the largest floats, signs)
  // and with the skipped values left out.
  std::mt19937 rng(5);
  std::vector<float> v;
  std::vector<std::uint8_t> skip;
  for (int i = 0; i < 50000; ++i) {
    std::uint32_t bits = rng();
    if (((bits >> 23) & 0xff) == 0xff) bits &= ~(1u << 30);  // no inf or NaN
    float f;
    std::memcpy(&f, &bits, sizeof f);
    v.push_back(f);
    skip.push_back(rng() % 4 == 0 ? 1 : 0);
  }
  v.push_back(std::numeric_limits<float>::denorm_min()), skip.push_back(0);
  v.push_back(std::numeric_limits<float>::max()), skip.push_back(0);
  v.push_back(-std::numeric_limits<float>::max()), skip.push_back(0);
  v.push_back(-0.0f), skip.push_back(0);
  ExactSum one, all, allSkipping;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!skip[i]) one.add(v[i]);
  allSkipping.addAll(v.data(), v.size(), skip.data());
  one.normalise(), allSkipping.normalise();
  EXPECT_EQ(one.digits(), allSkipping.digits());
  ExactSum every;
  for (float f : v) every.add(f);
  all.addAll(v.data(), v.size());
  every.normalise(), all.normalise();
  EXPECT_EQ(every.digits(), all.digits());
  EXPECT_NE(every.digits(), one.digits());  // the skipped values did count for something
  // Long arrays are summed on every thread (a sum per exponent each): the same digits with any
  // number of threads, and from inside a parallel region, where it sums on one.
  const int threads = omp_get_max_threads();
  for (int t : {1, 2, 3, 7}) {
    omp_set_num_threads(t);
    ExactSum split;
    split.addAll(v.data(), v.size(), skip.data());
    split.normalise();
    EXPECT_EQ(split.digits(), one.digits()) << t << " threads";
  }
  omp_set_num_threads(threads);
  ExactSum nested;
#pragma omp parallel num_threads(2)
  {
#pragma omp single
    nested.addAll(v.data(), v.size(), skip.data());
  }
  nested.normalise();
  EXPECT_EQ(nested.digits(), one.digits());
  // Subnormals are exact too (add() once shifted their significand by a negative count).
  ExactSum tiny;
  tiny.add(std::numeric_limits<float>::denorm_min()), tiny.add(1e-40f), tiny.add(1e-40f);
  EXPECT_EQ(tiny.toDouble(), static_cast<double>(std::numeric_limits<float>::denorm_min()) +
                                 2.0 * static_cast<double>(1e-40f));
}

using test::fullCloud;
using test::kCloud;
using test::kSupport;
using test::placeCloud;

// The record of particle i as raw bits, field by field.
std::vector<std::uint32_t> bitsOf(const Particles& f, std::size_t i) {
  std::vector<std::uint32_t> bits;
  f.forEachField([&](const auto& field) {
    std::uint32_t v;
    std::memcpy(&v, &field[i], 4);
    bits.push_back(v);
  });
  return bits;
}

// What one rank held after one exchange: the cut and cell size, its particles' records by id.
struct Seen {
  Slabs slabs;
  float cellSize = 0;
  std::map<std::uint32_t, std::vector<std::uint32_t>> owned, ghosts;
  std::size_t local = 0;  // particles in the local arrays
};

constexpr int kSteps = 4;

// The exchanges of kSteps steps on `ranks` threads, driven as Simulation::step drives them (the
// exchange, the grid's sort and the new keys, the ghosts dropped), the particles moved between.
std::vector<std::vector<Seen>> exchangeSteps(int ranks, std::vector<std::uint64_t>& migratedSeen) {
  const Aabb domain{Vec3(0, 0, 0), Vec3(1.0f, 0.3f, 0.3f)};
  std::vector<std::vector<Seen>> seen(kSteps, std::vector<Seen>(ranks));
  migratedSeen.assign(ranks, 0);
  test::ThreadRanks threads(ranks);
  threads.run([&](Communicator& comm) {
    Particles fluid = comm.rank() == 0 ? fullCloud() : Particles{};
    Halo halo(comm, domain, kSupport);
    halo.adopt(fluid);
    grid::NeighbourGrid grid;
    std::vector<std::uint32_t> order, scratch;
    for (int step = 0; step < kSteps; ++step) {
      Seen& s = seen[step][comm.rank()];
      s.cellSize = halo.exchange(fluid, kSupport);
      s.slabs = halo.slabs();
      s.local = fluid.size();
      for (std::size_t i = 0; i < fluid.size(); ++i)
        (halo.ghost()[i] ? s.ghosts : s.owned)[fluid.id[i]] = bitsOf(fluid, i);
      grid.build(fluid.x.data(), fluid.y.data(), fluid.z.data(), fluid.size(), s.cellSize, order,
                 grid::NeighbourGrid::kExactCellSize);
      fluid.permute(order, scratch);
      halo.sorted(grid, order);
      halo.dropGhosts(fluid);
      placeCloud(fluid, step + 1);
    }
    migratedSeen[comm.rank()] = halo.stats().migratedAllRanks;
  });
  return seen;
}

TEST(Halo, OwnedParticlesAreEveryParticleOnceAndGhostsEqualABruteForceSearchAcrossFaces) {
  for (int ranks = 1; ranks <= 4; ++ranks) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    std::vector<std::uint64_t> counted;  // HaloStats::migratedAllRanks, per rank
    const auto seen = exchangeSteps(ranks, counted);
    std::uint64_t migrated = 0, beforeLast = 0;
    std::vector<int> before;
    for (int step = 0; step < kSteps; ++step) {
      SCOPED_TRACE("step " + std::to_string(step));
      // The truth: the whole cloud at this step, as one process holds it.
      Particles all = fullCloud();
      placeCloud(all, step);
      const std::vector<Seen>& at = seen[step];
      const Slabs& slabs = at[0].slabs;
      const double cs = at[0].cellSize;
      ASSERT_EQ(cs, double(kSupport));  // no growth at this density
      ASSERT_EQ(slabs.axis, 0);         // the domain's longest axis
      // Migration conserves the particles (and with them the mass, the same for each): every id
      // is owned by exactly one rank, its record unchanged, inside that rank's slab.
      std::vector<int> owner(all.size(), -1);
      for (int r = 0; r < ranks; ++r) {
        EXPECT_EQ(at[r].slabs.first, slabs.first) << "rank " << r << " cut elsewhere";
        EXPECT_EQ(at[r].local, at[r].owned.size() + at[r].ghosts.size())
            << "a particle twice on rank " << r;
        for (const auto& [id, bits] : at[r].owned) {
          ASSERT_LT(id, all.size());
          EXPECT_EQ(owner[id], -1) << "particle " << id << " owned twice";
          owner[id] = r;
          EXPECT_EQ(bits, bitsOf(all, id)) << "particle " << id << " changed on its way";
          const auto plane = static_cast<long long>(std::floor(double(all.x[id]) / cs));
          EXPECT_EQ(slabs.ownerOf(plane), r) << "particle " << id << " outside its owner's slab";
        }
      }
      for (std::size_t j = 0; j < all.size(); ++j) {
        ASSERT_NE(owner[j], -1) << "particle " << j << " lost in migration";
        if (!before.empty()) migrated += owner[j] != before[j];
      }
      if (step == kSteps - 2) beforeLast = migrated;
      before = owner;

      for (int r = 0; r < ranks; ++r) {
        SCOPED_TRACE("rank " + std::to_string(r));
        const Seen& s = at[r];
        // Brute force across the faces: every other rank's particle closer than kGhostPlanes
        // cell widths to this rank's slab [first[r], first[r + 1]) x cs, along the axis.
        const double lo = double(slabs.first[r]) * cs, hi = double(slabs.first[r + 1]) * cs;
        std::set<std::uint32_t> expected, got;
        for (std::size_t j = 0; j < all.size(); ++j) {
          if (owner[j] == r) continue;
          const double x = all.x[j], gap = x < lo ? lo - x : x >= hi ? x - hi : 0.0;
          if (gap < kGhostPlanes * cs) expected.insert(static_cast<std::uint32_t>(j));
        }
        for (const auto& [id, bits] : s.ghosts) {
          got.insert(id);
          EXPECT_EQ(bits, bitsOf(all, id)) << "ghost " << id << " is not its owner's copy";
        }
        EXPECT_EQ(got, expected);
        if (ranks > 1) {
          EXPECT_GT(got.size(), 0u);
        }
        // And what the passes need is there (a brute-force pair search in 3D): every neighbour
        // within the support of an owned particle, and every neighbour of those (their
        // densities are computed here, docs/scaling.md).
        auto present = [&](std::size_t j) {
          const auto id = static_cast<std::uint32_t>(j);
          return s.owned.count(id) + s.ghosts.count(id) > 0;
        };
        std::vector<char> near(all.size(), 0);
        for (std::size_t i = 0; i < all.size(); ++i) {
          if (owner[i] != r) continue;
          for (std::size_t j = 0; j < all.size(); ++j)
            if (owner[j] != r && (all.position(i) - all.position(j)).norm() <= kSupport)
              near[j] = 1;
        }
        for (std::size_t g = 0; g < all.size(); ++g) {
          if (!near[g]) continue;
          ASSERT_TRUE(present(g)) << "neighbour " << g << " of an owned particle missing";
          for (std::size_t j = 0; j < all.size(); ++j) {
            if ((all.position(g) - all.position(j)).norm() <= kSupport) {
              ASSERT_TRUE(present(j)) << "neighbour " << j << " of ghost " << g << " missing";
            }
          }
        }
      }
    }
    if (ranks > 1) {
      EXPECT_GT(migrated, kCloud / 10) << "the cloud's motion should cross faces";
    }
    // The run's figure (docs/benchmarks.md, "Scale"): every rank tells the same count, that of
    // the exchanges after the first up to the one before the last.
    for (std::uint64_t c : counted) EXPECT_EQ(c, beforeLast);
  }
}

TEST(Halo, AttachedArraysAndRefreshedGhostsFollowTheirParticles) {
  // DFSPH's needs (sim/solver/Dfsph.cpp): an attached per-particle array (the warm start) travels with
  // its particle through migration, to its ghosts, through the sorts and into the gathered frame;
  // refreshGhosts() overwrites every ghost's copy with its owner's current value, along the
  // ghost lists kept through the key order and the grid sort.
  const Aabb domain{Vec3(0, 0, 0), Vec3(1.0f, 0.3f, 0.3f)};
  auto warmOf = [](std::uint32_t id, int step) { return 0.5f * id + 1000.0f * step; };
  auto velocityOf = [](std::uint32_t id, int step) { return -0.25f * id - 7.0f * step; };
  for (int ranks = 1; ranks <= 4; ++ranks) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    test::ThreadRanks threads(ranks);
    std::vector<int> wrongWarm(ranks, 0), staleGhosts(ranks, 0), ghostsSeen(ranks, 0);
    std::vector<int> wrongGathered(ranks, 0);
    std::vector<std::size_t> gathered(ranks, 0);
    threads.run([&](Communicator& comm) {
      const int me = comm.rank();
      Particles fluid = me == 0 ? fullCloud() : Particles{};
      std::vector<float> warm;  // empty until the first exchange sizes it, as alone
      Halo halo(comm, domain, kSupport);
      halo.adopt(fluid);
      halo.attach(warm);
      grid::NeighbourGrid grid;
      std::vector<std::uint32_t> order, scratch;
      for (int step = 0; step < kSteps; ++step) {
        const float cs = halo.exchange(fluid, kSupport);
        EXPECT_EQ(warm.size(), fluid.size());
        for (std::size_t i = 0; i < fluid.size(); ++i)  // step 0: exchange() gave 0
          wrongWarm[me] += warm[i] != (step == 0 ? 0.0f : warmOf(fluid.id[i], step - 1));
        grid.build(fluid.x.data(), fluid.y.data(), fluid.z.data(), fluid.size(), cs, order,
                   grid::NeighbourGrid::kExactCellSize);
        fluid.permute(order, scratch);
        halo.sorted(grid, order);
        // The owners change their velocities; the ghosts' copies are stale until the refresh.
        for (std::size_t i = 0; i < fluid.size(); ++i)
          if (!halo.ghost()[i]) fluid.vx[i] = velocityOf(fluid.id[i], step);
        halo.refreshGhosts({&fluid.vx});
        for (std::size_t i = 0; i < fluid.size(); ++i) {
          if (!halo.ghost()[i]) continue;
          ++ghostsSeen[me];
          staleGhosts[me] += fluid.vx[i] != velocityOf(fluid.id[i], step);
        }
        for (std::size_t i = 0; i < fluid.size(); ++i) warm[i] = warmOf(fluid.id[i], step);
        halo.dropGhosts(fluid);
        EXPECT_EQ(warm.size(), fluid.size());
        placeCloud(fluid, step + 1);
      }
      std::vector<std::vector<float>> attached;
      const Particles all = halo.gather(fluid, &attached);
      if (me != 0) return;
      gathered[me] = all.size();
      EXPECT_EQ(attached.size(), 1u);
      if (attached.size() != 1 || attached[0].size() != all.size()) return;
      for (std::size_t k = 0; k < all.size(); ++k)
        wrongGathered[me] += attached[0][k] != warmOf(all.id[k], kSteps - 1);
    });
    for (int r = 0; r < ranks; ++r) {
      EXPECT_EQ(wrongWarm[r], 0) << "rank " << r;
      EXPECT_EQ(staleGhosts[r], 0) << "rank " << r;
      EXPECT_EQ(ranks > 1, ghostsSeen[r] > 0) << "rank " << r;
      EXPECT_EQ(wrongGathered[r], 0);
    }
    EXPECT_EQ(gathered[0], kCloud);
  }
}

}  // namespace
}  // namespace sph::ranks
