// A scene too big for the machine is refused before anything is allocated, with one line naming the
// estimate, the machine's memory and the key to change; and the estimate (sim/run/MemoryEstimate.h) is
// within 20% of the measured peak resident memory of real runs.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>

#include "job/MachineMemory.h"
#include "sim/solver/Boundary.h"
#include "sim/run/MemoryEstimate.h"
#include "tests/CacheTestSupport.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using test::estimatedBytes;
using test::measure;
using test::Measured;

// These tests measure the program's own memory, which AddressSanitizer changes: it reserves
// terabytes of address space for its shadow memory (no run fits under `ulimit -v`) and gives every
// allocation redzones and a quarantine (the resident memory is no longer the program's). They run
// in every build without it; the sanitize build skips them, saying so.
#if defined(__SANITIZE_ADDRESS__)
#define SKIP_UNDER_ADDRESS_SANITIZER() \
  GTEST_SKIP() << "measures the program's memory, which AddressSanitizer changes"
#else
#define SKIP_UNDER_ADDRESS_SANITIZER() static_cast<void>(0)
#endif

struct EstimatedRun {
  const char* scene;    // in scenes/
  const char* spacing;  // solver.spacing
  const char* quality;  // "default" (WCSPH) or "accurate" (DFSPH, which stores its pairs)
  const char* end;      // --end (s)
};

class MemoryEstimateRuns : public ::testing::TestWithParam<EstimatedRun> {};

TEST_P(MemoryEstimateRuns, IsWithinTwentyPercentOfThePeakResidentMemory) {
  SKIP_UNDER_ADDRESS_SANITIZER();
  const EstimatedRun r = GetParam();
  const std::string run = "env OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run " +
                          test::sourcePath(std::string("scenes/") + r.scene) +
                          " --set solver.spacing=" + r.spacing + " --set quality=" + r.quality +
                          " --end " + r.end + " --threads 2";
  const Measured m = measure(run + " --verbose");
  ASSERT_EQ(m.exitCode, 0) << m.output;
  const double estimate = estimatedBytes(m.output);
  ASSERT_GT(estimate, 0) << m.output;
  std::printf("%s, spacing %s, %s, to %s s: estimate %.1f MB, peak resident %.1f MB\n", r.scene,
              r.spacing, r.quality, r.end, estimate / 1e6, m.peakBytes / 1e6);
  EXPECT_NEAR(estimate / m.peakBytes, 1.0, 0.2) << m.output;
}

// WCSPH at 156k, 420k and 913k fluid particles; DFSPH at 156k and 420k, and through an impact:
// the peer's dam break (59k particles) to 0.2 s, where its falling cube has met the floor and
// spread; the pairs DFSPH stores follow the rows of cells the fluid moves through, so a store
// that kept each row's largest room (before 2026-11-26) peaked at 1.4x the estimate there.
INSTANTIATE_TEST_SUITE_P(
    DamBreak, MemoryEstimateRuns,
    ::testing::Values(EstimatedRun{"dam_break.json", "0.0025", "default", "0.002"},
                      EstimatedRun{"dam_break.json", "0.0018", "default", "0.002"},
                      EstimatedRun{"dam_break.json", "0.0014", "default", "0.002"},
                      EstimatedRun{"dam_break.json", "0.0025", "accurate", "0.002"},
                      EstimatedRun{"dam_break.json", "0.0018", "accurate", "0.002"},
                      EstimatedRun{"peer_dam_break.json", "0.025", "accurate", "0.2"}));

// `sphsplat run scenes/SCENE ARGS --end 0.01` under `ulimit -v` of 600 MB.
Measured runUnderSixHundredMegabytes(const std::string& scene, const std::string& args) {
  return measure("sh -c 'ulimit -v 600000; exec " + test::sphsplatBinary() + " run " +
                 test::sourcePath("scenes/" + scene) + " " + args + " --end 0.01'");
}

TEST(MemoryEstimate, ASceneTooBigForItsMemoryIsRefusedBeforeItAllocates) {
  SKIP_UNDER_ADDRESS_SANITIZER();
  // 0.6 mm: 1.1e7 fluid particles, about 1.1 GB; under `ulimit -v` of 600 MB it cannot fit.
  const Measured m = runUnderSixHundredMegabytes("dam_break.json", "--set solver.spacing=0.0006");
  EXPECT_EQ(m.exitCode, 2) << m.output;
  EXPECT_TRUE(std::regex_search(
      m.output, std::regex("dam_break.json: solver.spacing: this scene needs about [0-9.]+ GB "
                           "\\([0-9.e+]+ fluid particles, [0-9.e+]+ boundary particles\\); the "
                           "machine has [0-9.]+ GB, of which ulimit -v leaves [0-9.]+ MB; raise "
                           "solver.spacing")))
      << m.output;
  EXPECT_EQ(m.output.find('\n'), m.output.size() - 1) << "one line";
  EXPECT_LT(m.peakBytes, 100e6) << "refused before allocating";
}

TEST(MemoryEstimate, AHugeNozzleIsNamed) {
  const Measured m =
      measure(test::sphsplatBinary() + " run " + test::sourcePath("scenes/pour.json") +
              " --set 'emitters[0].radius=1000' --end 0.1");
  EXPECT_EQ(m.exitCode, 2) << m.output;
  EXPECT_NE(m.output.find("pour.json: emitters[0].radius: this scene needs about"),
            std::string::npos)
      << m.output;
#if !defined(__SANITIZE_ADDRESS__)  // (whose shadow memory and quarantine are not the program's)
  EXPECT_LT(m.peakBytes, 100e6);
#endif
}

TEST(MemoryEstimate, ARainTooBigIsRefusedNamingItsBudget) {
  SKIP_UNDER_ADDRESS_SANITIZER();
  // 10^8 drops (rain.count's maximum) are about 3 GB; under `ulimit -v` of 600 MB they cannot
  // fit, and the run stops before spawning one.
  const Measured m = runUnderSixHundredMegabytes("rain_pour.json", "--set rain.count=100000000");
  EXPECT_EQ(m.exitCode, 2) << m.output;
  EXPECT_TRUE(std::regex_search(
      m.output, std::regex("rain_pour.json: rain.count: this scene needs about [0-9.]+ GB "
                           "\\(.*, 1e\\+08 rain drops\\); .*; lower rain.count")))
      << m.output;
  EXPECT_LT(m.peakBytes, 100e6) << "refused before allocating";
}

TEST(MemoryEstimate, IsWithinTwentyPercentWithFourMillionRainDrops) {
  SKIP_UNDER_ADDRESS_SANITIZER();
  const std::string dir = test::makeTempDir();
  std::ofstream(dir + "/rain.json") << R"({
  "solver": {"spacing": 0.025, "end_time": 0.02},
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.2, 0.2, 0.15]}],
  "fluids": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.15]}],
  "camera": {"position": [0.5, 0.4, 0.5], "target": [0.1, 0.05, 0.075], "fov": 40},
  "rain": {"count": 4000000, "near": 0.05, "far": 1, "seed": 3},
  "output": {"fps": 50}
})";
  const Measured m = measure("env OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run " +
                             dir + "/rain.json --threads 2 --verbose -o " + dir + "/rain.h5");
  ASSERT_EQ(m.exitCode, 0) << m.output;
  const double estimate = estimatedBytes(m.output);
  std::printf("4e6 rain drops: estimate %.1f MB, peak resident %.1f MB\n", estimate / 1e6,
              m.peakBytes / 1e6);
  EXPECT_NEAR(estimate / m.peakBytes, 1.0, 0.2) << m.output;
}

// The counts behind the estimate follow the samplers they predict.
TEST(MemoryEstimate, BoundaryCountsMatchTheSamplers) {
  const Aabb domain{Vec3(-0.2f, -0.2f, -0.2f), Vec3(0.5f, 0.5f, 0.5f)};
  std::vector<scene::BoundaryShape> shapes(4);
  shapes[0].kind = scene::BoundaryShape::Kind::Tank, shapes[0].lo = Vec3(0, 0, 0),
  shapes[0].hi = Vec3(0.3f, 0.2f, 0.1f);
  shapes[1] = shapes[0], shapes[1].openTop = false;
  shapes[2] = shapes[0], shapes[2].kind = scene::BoundaryShape::Kind::Block;
  shapes[3].kind = scene::BoundaryShape::Kind::Cup, shapes[3].centre = Vec3(0.1f, 0, 0.1f),
  shapes[3].radius = 0.05f, shapes[3].height = 0.08f;
  for (const scene::BoundaryShape& s : shapes) {
    for (int layers : {1, 2, 3}) {
      const double counted = solver::countBoundarySamples(s, domain, 0.01f, layers);
      const double sampled =
          static_cast<double>(solver::sampleBoundaryShape(s, domain, 0.01f, layers).size());
      EXPECT_NEAR(counted, sampled, 0.02 * sampled) << static_cast<int>(s.kind) << " " << layers;
    }
  }
}

// On K processes each rank estimates its own share (RankShare): the fluid shared out, the
// boundary whole, and what only rank 0 holds when it gathers the frames.
TEST(MemoryEstimate, ARankHoldsItsShareOfTheFluidAndAllOfTheBoundary) {
  const scene::Scene scene = test::shippedScene("dam_break", {"solver.spacing=0.0021"});
  const run::MemoryEstimate one = run::estimateMemory(scene);
  const run::MemoryEstimate k1 = run::estimateMemory(scene, {1, true, false});
  const run::MemoryEstimate k2 = run::estimateMemory(scene, {2, true, false});
  const run::MemoryEstimate k4 = run::estimateMemory(scene, {4, true, false});
  const run::MemoryEstimate gathering = run::estimateMemory(scene, {2, true, true});
  EXPECT_EQ(one.ranks, 1);
  EXPECT_EQ(k4.ranks, 4);
  // The distributed path's keys, places and buffers cost more than one process's arrays.
  EXPECT_GT(k1.bytes, one.bytes * 1.3);
  EXPECT_LT(k2.bytes, k1.bytes);
  EXPECT_LT(k4.bytes, k2.bytes);
  // Shares of 1/K: going from 2 to 4 ranks saves about half what going from 1 to 2 did.
  EXPECT_NEAR((k2.bytes - k4.bytes) / (k1.bytes - k2.bytes), 0.5, 0.15);
  EXPECT_EQ(k4.boundaryParticles, one.boundaryParticles);
  EXPECT_EQ(k2.rootOnlyBytes, 0.0);
  EXPECT_GT(gathering.rootOnlyBytes, 100 * one.fluidParticles) << "a whole frame on rank 0";
  EXPECT_NEAR(gathering.bytes - k2.bytes, gathering.rootOnlyBytes, 1.0);
}

// The check's decision (job/MachineMemory.h): a rank's share against what a process may use, and
// the ranks of one machine together against what it has free.
TEST(MemoryEstimate, RanksThatFitAloneButNotTogetherAreRefusedNamingTheirSum) {
  scene::Scene scene = test::shippedScene("dam_break", {"solver.spacing=0.0021"});
  scene.sourcePath = "dam.json";
  const run::MemoryEstimate e = run::estimateMemory(scene, {4, true, false});
  job::MachineMemory machine;
  machine.totalBytes = 64e9;
  machine.availableBytes = machine.sharedBytes = 1.5 * e.bytes;
  EXPECT_FALSE(job::memoryRefusal(scene, e, machine, {1, true, true}))
      << "one rank on each machine fits";
  const std::optional<std::string> together =
      job::memoryRefusal(scene, e, machine, {4, true, true});
  ASSERT_TRUE(together);
  EXPECT_EQ(together->rfind("dam.json: solver.spacing: this scene needs about ", 0), 0u)
      << *together;
  EXPECT_NE(together->find("a process on 4 processes"), std::string::npos) << *together;
  EXPECT_NE(together->find("the 4 processes on this machine need about"), std::string::npos)
      << *together;
  EXPECT_NE(together->find("spread the processes over more machines"), std::string::npos)
      << *together;
  // A process limit (ulimit -v) under one rank's share: more processes would each need less.
  machine.availableBytes = 0.5 * e.bytes, machine.limitedBy = "ulimit -v";
  machine.sharedBytes = 100 * e.bytes;
  const std::optional<std::string> alone = job::memoryRefusal(scene, e, machine, {1, true, true});
  ASSERT_TRUE(alone);
  EXPECT_NE(alone->find("of which ulimit -v leaves"), std::string::npos) << *alone;
  EXPECT_NE(alone->find("run on more processes"), std::string::npos) << *alone;
  EXPECT_EQ(alone->find("on this machine need"), std::string::npos) << *alone;
}

// What only rank 0 holds (a gathered frame, without parallel HDF5) is asked of rank 0 and of the
// machine rank 0 runs on, not of every rank.
TEST(MemoryEstimate, RankZerosOwnPartIsAskedOfRankZeroAlone) {
  scene::Scene scene = test::shippedScene("dam_break", {"solver.spacing=0.0021"});
  scene.sourcePath = "dam.json";
  const run::MemoryEstimate e = run::estimateMemory(scene, {4, true, true});
  ASSERT_GT(e.rootOnlyBytes, 0.3 * e.bytes);
  job::MachineMemory machine;
  machine.totalBytes = 64e9;
  // Room for a rank without rank 0's part, not for rank 0.
  machine.availableBytes = machine.sharedBytes = e.bytes - 0.5 * e.rootOnlyBytes;
  EXPECT_TRUE(job::memoryRefusal(scene, e, machine, {1, true, true})) << "rank 0";
  EXPECT_FALSE(job::memoryRefusal(scene, e, machine, {1, false, false})) << "another rank";
  // Two other ranks on a machine without rank 0 need twice a share, no gathered frame.
  machine.availableBytes = e.bytes, machine.sharedBytes = 2 * (e.bytes - e.rootOnlyBytes) + 1;
  EXPECT_FALSE(job::memoryRefusal(scene, e, machine, {2, false, false}));
  EXPECT_TRUE(job::memoryRefusal(scene, e, machine, {2, false, true})) << "rank 0 is there";
}

}  // namespace
}  // namespace sph
