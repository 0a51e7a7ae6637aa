// A distributed start (sim/run/StartSlab.h, docs/scaling.md "A distributed start"): with K
// ranks as threads (tests/ThreadRanks.h), each rank's Simulation generates only its slab of the
// starting fluid, and together the ranks hold the single process's initialFluid exactly once:
// the same ids, the same bits, each particle on the rank whose slab holds it, in the order of its
// id. The cut is the one the first exchange makes (nothing migrates), and until that exchange a
// frame's places are the keys, found with no collective.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <tuple>
#include <vector>

#include "io/scene/SceneLoader.h"
#include "sim/run/Simulation.h"
#include "sim/ranks/Halo.h"
#include "tests/ThreadRanks.h"

namespace sph::ranks {
namespace {

// A tank longest along `axis` holding a box of water against its walls (the points within 0.4
// spacing of a wall are dropped), a moving box and a sphere: three blocks, rows of different
// lengths, points skipped inside a block.
std::string scene(int axis) {
  const char* size[3] = {"[0.8, 0.3, 0.2]", "[0.2, 0.8, 0.3]", "[0.3, 0.2, 0.8]"};
  return std::string(R"({
  "name": "start_slab",
  "solver": {"spacing": 0.02, "support": 2.0, "end_time": 0.1},
  "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.16, 0.14, 0.12]},
             {"type": "box", "min": [0.05, 0.15, 0.05], "max": [0.13, 0.19, 0.11],
              "velocity": [0.3, -0.5, 0.1]},
             {"type": "sphere", "centre": [0.1, 0.1, 0.16], "radius": 0.035}],
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": )") +
         size[axis] + R"(}]
})";
}

bool sameBits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(StartSlab, EachRankGeneratesItsSlabAndTogetherTheyHoldTheSingleProcesssFluid) {
  for (int axis = 0; axis < 3; ++axis) {
    const scene::Scene s = io::scene::parseScene(scene(axis), "start_slab.json");
    const run::Simulation alone(s);
    const Particles& all = alone.fluid();
    ASSERT_GT(all.size(), 300u);
    for (int k = 1; k <= 4; ++k) {
      SCOPED_TRACE("slabs across axis " + std::to_string(axis) + ", " + std::to_string(k) +
                   " ranks");
      std::vector<Particles> parts(k);
      std::vector<HaloStats> stats(k);
      std::vector<std::vector<std::uint64_t>> places(k);
      std::vector<int> ownedElsewhere(k, 0), slabAxis(k, -1);
      std::vector<std::uint32_t> nextId(k);
      std::vector<float> maxSpeed(k);
      test::ThreadRanks threads(k);
      threads.run([&](Communicator& comm) {
        const int me = comm.rank();
        Halo halo(comm, s.domain, s.solver.supportRadius());
        run::Simulation sim(s, halo);
        sim.setHalo(&halo);
        parts[me] = sim.fluid();
        nextId[me] = sim.runState().nextId;
        maxSpeed[me] = sim.runState().maxSpeed;
        slabAxis[me] = halo.slabs().axis;
        for (std::size_t i = 0; i < sim.fluid().size(); ++i)
          ownedElsewhere[me] += halo.owns(sim.fluid().position(i)) ? 0 : 1;
        places[me] = halo.globalPlaces();
        Particles copy = sim.fluid();
        halo.exchange(copy, sim.params().h);  // the first step's: it finds the same cut
        halo.dropGhosts(copy);
        stats[me] = halo.stats();
      });
      std::vector<int> seen(all.size(), 0);
      for (int r = 0; r < k; ++r) {
        SCOPED_TRACE("rank " + std::to_string(r));
        const Particles& mine = parts[r];
        EXPECT_EQ(slabAxis[r], axis);
        EXPECT_EQ(nextId[r], all.size());
        EXPECT_TRUE(sameBits(maxSpeed[r], alone.runState().maxSpeed));
        EXPECT_EQ(ownedElsewhere[r], 0) << "particles outside this rank's slab";
        EXPECT_EQ(stats[r].migrated, 0u) << "the first exchange moved particles";
        EXPECT_EQ(stats[r].placesBytesReceived, 0u);
        ASSERT_EQ(places[r].size(), mine.size());
        for (std::size_t i = 0; i < mine.size(); ++i) {
          const std::uint32_t id = mine.id[i];
          ASSERT_LT(id, all.size());
          if (i > 0) {
            EXPECT_LT(mine.id[i - 1], id) << "not in the starting order";
          }
          EXPECT_EQ(places[r][i], id);
          ++seen[id];
          // The single process's particle `id` is its id-th (initialFluid counts them in order).
          ASSERT_EQ(all.id[id], id);
          int differing = 0;  // every field of the particle, bit for bit
          std::apply(
              [&](auto... member) {
                ((differing += std::memcmp(&(mine.*member)[i], &(all.*member)[id],
                                           sizeof((all.*member)[id])) != 0),
                 ...);
              },
              Particles::fields());
          EXPECT_EQ(differing, 0) << "particle " << id << " differs from the single process's";
        }
      }
      for (std::size_t id = 0; id < all.size(); ++id)
        ASSERT_EQ(seen[id], 1) << "particle " << id << " held " << seen[id] << " times";
      if (k > 1) {
        int holding = 0;
        for (const Particles& p : parts) holding += p.empty() ? 0 : 1;
        EXPECT_GT(holding, 1) << "one rank generated everything";
      }
    }
  }
}

TEST(StartSlab, AResumingRankGeneratesNoStart) {
  // A distributed resume reads each rank's part of the cache's frame (job/distributed/DistributedResume.h):
  // its Simulation is built without the starting slab it would drop, the boundary as always.
  const scene::Scene s = io::scene::parseScene(scene(0), "start_slab.json");
  std::vector<std::size_t> fluid(2, 1), boundary(2, 0);
  std::vector<std::uint32_t> nextId(2, 1);
  test::ThreadRanks threads(2);
  threads.run([&](Communicator& comm) {
    Halo halo(comm, s.domain, s.solver.supportRadius());
    const run::Simulation sim(s, halo, run::Simulation::Start::Empty);
    fluid[comm.rank()] = sim.fluid().size();
    boundary[comm.rank()] = sim.boundary().particles().size();
    nextId[comm.rank()] = sim.runState().nextId;
  });
  const run::Simulation alone(s);
  for (int r = 0; r < 2; ++r) {
    EXPECT_EQ(fluid[r], 0u) << "rank " << r;
    EXPECT_EQ(nextId[r], 0u) << "rank " << r;
    EXPECT_EQ(boundary[r], alone.boundary().particles().size()) << "rank " << r;
  }
}

}  // namespace
}  // namespace sph::ranks
