// Halo::globalPlaces (sim/ranks/HaloPlaces.cpp): the places each rank writes its particles to when
// the ranks write a cache frame together (job/distributed/CollectiveCacheSink.h), against the brute force
// they replace: every rank's particles gathered on every rank and sorted by key
// (Halo::allGather's `mine`, the all-gather of every key that globalPlaces did before). K = 1..4
// ranks as threads (tests/ThreadRanks.h), slabs across x, y and z, after each way a run reaches
// a frame: sorted steps (WCSPH, DFSPH), a second exchange after the sort (the `exact` collision
// pass), particles emitted after the sort, no sort at all (the particle model), and ranks that
// own nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/grid/NeighbourGrid.h"
#include "sim/ranks/Halo.h"
#include "tests/HaloCloud.h"
#include "tests/ThreadRanks.h"

namespace sph::ranks {
namespace {

using test::CloudShape;
using test::kCloud;
using test::kSupport;

// How the run reached the frame.
enum class Before {
  Sorted,     // steps of exchange, sort, ghosts dropped: every key follows the rank order
  Exchanged,  // then the particles moved and an exchange without a sort migrated some
  Emitted,    // particles emitted every step (sorted in), then more and an exchange without a
              // sort: their keys are kEmitted | id, spread over the ranks by migration
  Unsorted,   // exchanges and emissions but never a sort: the keys of the starting order
};

const char* nameOf(Before b) {
  switch (b) {
    case Before::Sorted:
      return "sorted";
    case Before::Exchanged:
      return "exchanged after the sort";
    case Before::Emitted:
      return "emitted after the sort";
    case Before::Unsorted:
      return "never sorted";
  }
  return "";
}

constexpr int kSteps = 4;
constexpr std::uint32_t kEmitPerStep = 30;

struct Outcome {
  std::vector<std::vector<std::uint64_t>> places, reference;  // per rank, per particle
  std::vector<HaloStats> stats;                               // per rank
  std::uint64_t total = 0;
  // HaloStats::placesStrays summed over the ranks: the keys placed by a rank other than their
  // holder's count, or by the share of the keys after every cell key.
  std::uint64_t strays() const {
    std::uint64_t n = 0;
    for (const HaloStats& s : stats) n += s.placesStrays;
    return n;
  }
};

Outcome placesAfter(int ranks, CloudShape shape, Before before) {
  Outcome out;
  out.places.resize(ranks), out.reference.resize(ranks), out.stats.resize(ranks);
  const Aabb domain = test::cloudDomain(shape);
  test::ThreadRanks threads(ranks);
  threads.run([&](Communicator& comm) {
    const int me = comm.rank();
    Particles fluid = me == 0 ? test::fullCloud(shape) : Particles{};
    Halo halo(comm, domain, kSupport);
    halo.adopt(fluid);
    grid::NeighbourGrid grid;
    std::vector<std::uint32_t> order, scratch;
    std::uint32_t nextId = kCloud;
    // As Simulation::emitParticles: the rank holding the nozzle adds them, every rank counts ids.
    const auto emit = [&] {
      const bool mine = halo.owns(0.5f * (domain.lo + domain.hi));
      for (std::uint32_t k = 0; k < kEmitPerStep; ++k, ++nextId)
        if (mine) test::appendCloudParticle(fluid, nextId, shape);
    };
    const bool emits = before == Before::Emitted || before == Before::Unsorted;
    for (int step = 0; step < kSteps; ++step) {
      if (emits) emit();
      const float cs = halo.exchange(fluid, kSupport);
      if (before != Before::Unsorted) {
        grid.build(fluid.x.data(), fluid.y.data(), fluid.z.data(), fluid.size(), cs, order,
                   grid::NeighbourGrid::kExactCellSize);
        fluid.permute(order, scratch);
        halo.sorted(grid, order);
      }
      halo.dropGhosts(fluid);
      test::placeCloud(fluid, step + 1, shape);
    }
    if (before == Before::Exchanged || before == Before::Emitted) {
      if (before == Before::Emitted) emit();
      halo.exchange(fluid, kSupport);
      halo.dropGhosts(fluid);
    }
    out.places[me] = halo.globalPlaces();
    std::vector<std::uint32_t> mine;
    halo.allGather(fluid, mine);
    out.reference[me].assign(mine.begin(), mine.end());
    out.stats[me] = halo.stats();
    const std::uint64_t total = halo.globalCount(fluid.size());
    if (me == 0) out.total = total;
  });
  return out;
}

// Every rank's places are the brute force's, and together every place of the frame once.
void expectTheBruteForce(const Outcome& out) {
  std::vector<int> taken(out.total, 0);
  for (std::size_t r = 0; r < out.places.size(); ++r) {
    SCOPED_TRACE("rank " + std::to_string(r));
    ASSERT_EQ(out.places[r].size(), out.reference[r].size());
    EXPECT_EQ(out.places[r], out.reference[r]);
    for (std::uint64_t p : out.places[r]) {
      ASSERT_LT(p, out.total);
      ++taken[p];
    }
  }
  EXPECT_EQ(std::count(taken.begin(), taken.end(), 1), static_cast<long>(out.total));
}

TEST(HaloPlaces, EqualTheAllGatherOfEveryKeyOnEverySlabAxis) {
  for (const Before before : {Before::Sorted, Before::Exchanged, Before::Emitted})
    for (int axis = 0; axis < 3; ++axis)
      for (int ranks = 1; ranks <= 4; ++ranks) {
        SCOPED_TRACE(std::string(nameOf(before)) + ", slabs across axis " + std::to_string(axis) +
                     ", " + std::to_string(ranks) + " ranks");
        const Outcome out = placesAfter(ranks, CloudShape{axis, false}, before);
        const std::uint32_t emitted = before == Before::Emitted ? (kSteps + 1) * kEmitPerStep : 0;
        ASSERT_EQ(out.total, kCloud + emitted);
        expectTheBruteForce(out);
        EXPECT_EQ(out.stats[0].placesCalls, 1u);
        if (before == Before::Sorted) {
          // Every key is placed where it is: a counter per unit and no key sent (the all-gather
          // received 8 bytes for each particle of the other ranks).
          EXPECT_EQ(out.strays(), 0u);
          for (const HaloStats& s : out.stats)
            if (ranks > 1) {
              EXPECT_LT(s.placesBytesReceived, 8u * kCloud / 4);
            }
        }
        if (before == Before::Exchanged && ranks > 1) {
          EXPECT_GT(out.strays(), 0u) << "the motion should migrate particles after the sort";
        }
        if (before == Before::Emitted) {  // the fresh ones at least
          EXPECT_GE(out.strays(), kEmitPerStep);
        }
      }
}

TEST(HaloPlaces, EqualTheAllGatherWhenTheKeysWereNeverSorted) {
  // The particle model migrates without sorting: every key is the starting order's (rank 0's
  // fluid) or an emitted one, spread over the ranks, so every key goes to the rank of its share
  // of them and comes back placed. No rank receives every key.
  for (int ranks = 1; ranks <= 4; ++ranks) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const Outcome out = placesAfter(ranks, CloudShape{}, Before::Unsorted);
    ASSERT_EQ(out.total, kCloud + kSteps * kEmitPerStep);
    expectTheBruteForce(out);
    EXPECT_EQ(out.strays(), out.total);
    // Each rank receives the other ranks' keys of its share and the places of its keys that
    // other ranks' shares hold, 8 bytes each: about 16 N (K - 1) / K^2 bytes where the all-gather
    // gave every rank every other rank's key, 8 N (K - 1) / K (level at K = 2).
    if (ranks > 2) {
      for (std::size_t r = 0; r < out.stats.size(); ++r)
        EXPECT_LT(out.stats[r].placesBytesReceived, 8 * (out.total - out.places[r].size()))
            << "rank " << r;
    }
  }
}

TEST(HaloPlaces, EqualTheAllGatherWhenRanksOwnNothing) {
  // A sheet two cell planes thick: the cut by particle counts leaves ranks without particles
  // (they still take part in every collective, with nothing to place).
  for (const Before before : {Before::Sorted, Before::Emitted})
    for (int axis = 0; axis < 3; ++axis)
      for (int ranks = 2; ranks <= 4; ++ranks) {
        SCOPED_TRACE(std::string(nameOf(before)) + ", slabs across axis " + std::to_string(axis) +
                     ", " + std::to_string(ranks) + " ranks");
        const Outcome out = placesAfter(ranks, CloudShape{axis, true}, before);
        expectTheBruteForce(out);
        if (ranks == 4) {
          const auto empty = std::count_if(out.places.begin(), out.places.end(),
                                           [](const auto& p) { return p.empty(); });
          EXPECT_GE(empty, 1) << "the sheet should leave a rank empty";
        }
      }
}

}  // namespace
}  // namespace sph::ranks
