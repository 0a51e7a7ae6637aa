// On K processes each rank checks its own share of the scene's memory (sim/run/MemoryEstimate.h,
// RankShare; job/MachineMemory.h): the estimate a rank prints is held against the largest rank's
// peak resident memory, as tests/test_memory_estimate.cpp holds one process's.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "tests/MpiTestSupport.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

// The dam break at 262,710 fluid particles, two frames: with K = 1 (the distributed path's keys
// and buffers on one rank) and K = 2 (each rank its slab, the boundary whole on both).
TEST(MpiMemory, ARanksEstimateIsWithinTwentyPercentOfTheLargestRanksPeak) {
  const std::string dir = test::makeTempDir();
  for (int k : {1, 2}) {
    const test::Measured m = test::measure(
        "env " +
        test::mpi::ranks(k, test::sourcePath("scenes/dam_break.json"),
                         "--set solver.spacing=0.0021 --set output.fps=10000 --end 0.0001 -o " +
                             dir + "/d" + std::to_string(k) + ".h5",
                         "--verbose"));
    ASSERT_EQ(m.exitCode, 0) << m.output;
    const double estimate = test::estimatedBytes(m.output);
    ASSERT_GT(estimate, 0) << m.output;
    std::printf("K = %d: estimate %.1f MB a rank, largest peak %.1f MB\n", k, estimate / 1e6,
                m.peakBytes / 1e6);
    EXPECT_NEAR(estimate / m.peakBytes, 1.0, 0.2) << m.output;
    if (k > 1) {
      EXPECT_NE(m.output.find("a process on 2 processes"), std::string::npos) << m.output;
    }
  }
}

}  // namespace
}  // namespace sph
