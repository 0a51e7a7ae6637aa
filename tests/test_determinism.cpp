// A run is bit-reproducible (Box2D test_determinism.c): the same scene gives the same state hash
// every time, and, since no reduction crosses threads, with any thread count. And it stays the
// same between commits: PinnedHash compares short runs with hashes written into this file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <string>

#include "sim/Parallel.h"
#include "sim/Simulation.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

std::uint64_t runPour(int threads) {
  setThreadCount(threads);
  // The pour exercises the emitter, cup, plane and sorting with a changing particle count.
  Simulation sim(test::shippedScene("pour", {"solver.spacing=0.008"}));
  sim.advanceTo(0.25);
  EXPECT_GT(sim.fluid().size(), 100u);
  return test::stateHash(sim.fluid());
}

TEST(Determinism, SameSceneSameThreadsGivesBitIdenticalState) {
  const int threads = std::max(2, omp_get_num_procs());
  EXPECT_EQ(runPour(threads), runPour(threads));
}

TEST(Determinism, ThreadCountDoesNotChangeTheResult) {
  EXPECT_EQ(runPour(1), runPour(2));
}

TEST(Determinism, TheHashSeesADifference) {
  setThreadCount(2);
  Simulation a(test::shippedScene("pour", {"solver.spacing=0.008"}));
  Simulation b(test::shippedScene("pour", {"solver.spacing=0.008", "solver.cfl=0.39"}));
  a.advanceTo(0.1);
  b.advanceTo(0.1);
  EXPECT_NE(test::stateHash(a.fluid()), test::stateHash(b.fluid()));
}

// ---- the pinned hashes ----------------------------------------------------------------------
//
// What a short run's final state hashes to (test::stateHash: FNV-1a over every Particles field's
// bytes, in id order). A change that moves any bit of any particle fails here, so a change of the
// results cannot slip in with a refactoring.
//
// The hash depends on the machine code of the neighbour passes, not only on the source:
// sim/SphPasses.cpp is built with -ffast-math and -march=native, so the reciprocal square-root
// estimate (12-bit vrsqrtps on AVX2, 14-bit vrsqrt14ps on AVX-512), FMA contraction and the
// vectoriser's choices (which follow the -march tuning) all reach the last bits. The pinned values
// are therefore keyed by the build: instruction set, -march tuning, compiler and build type. A
// build with no pinned value skips with the hash it got; the thread count never matters.
//
// To update deliberately (a change that is meant to change results): run
//   build/release/tests/test_determinism --gtest_filter='*Pinned*'
// on the unchanged commit first (it must pass), then on the change; replace the value printed in
// the failure, for every build key you can run, and say in the commit message why the results
// moved. Do not update a hash to make a refactoring pass: a refactoring must keep it.
std::string buildKey() {
  std::string key =
#if defined(__AVX512F__)
      "avx512";
#elif defined(__AVX2__)
      "avx2";
#elif defined(__AVX__)
      "avx";
#else
      "sse2";
#endif
#if defined(__tune_znver4__)
  key += "/znver4";
#elif defined(__tune_znver3__)
  key += "/znver3";
#elif defined(__tune_sapphirerapids__)
  key += "/sapphirerapids";
#elif defined(__tune_icelake_server__)
  key += "/icelake-server";
#elif defined(__tune_skylake_avx512__)
      key += "/skylake-avx512";
#elif defined(__tune_k8__)
      key += "/generic";
#else
      key += "/other";
#endif
#if defined(__clang__)
  key += "/clang" + std::to_string(__clang_major__);
#elif defined(__GNUC__)
  key += "/gcc" + std::to_string(__GNUC__);
#endif
#if defined(__SANITIZE_ADDRESS__)
  key += "/asan";
#elif defined(NDEBUG)
  key += "/release";
#else
  key += "/debug";
#endif
  return key;
}

struct PinnedRun {
  const char* name;
  std::uint64_t (*run)();
  // build key -> hash
  std::vector<std::pair<std::string, std::uint64_t>> hashes;
};

// The pour at a coarse spacing, its nozzle lowered to 4 cm above the cup's floor so the jet lands
// within the run: emitter, cup, sorting with a growing particle count.
std::uint64_t pinnedPour() {
  Simulation sim(
      test::shippedScene("pour", {"solver.spacing=0.008", "emitters[0].position=[0,0.04,0]"}));
  for (int s = 0; s < 300; ++s) sim.step();
  EXPECT_EQ(sim.fluid().size(), 90u);
  const auto& y = sim.fluid().y;
  EXPECT_LT(*std::min_element(y.begin(), y.end()), 0.01f) << "the jet has not reached the floor";
  return test::stateHash(sim.fluid());
}

// The dam break at a / dx = 10 with the other choices of kernel, EOS and walls: poly6 density,
// linear EOS, free-slip walls.
std::uint64_t pinnedDamBreak() {
  Simulation sim(
      test::shippedScene("dam_break", {"solver.spacing=0.0146", "solver.density_kernel=poly6",
                                       "solver.eos=linear", "solver.walls=slip"}));
  for (int s = 0; s < 40; ++s) sim.step();
  EXPECT_EQ(sim.fluid().size(), 800u);
  return test::stateHash(sim.fluid());
}

const std::vector<PinnedRun>& pinnedRuns() {
  static const std::vector<PinnedRun> runs = {
      // Zen 4 EPYC (AVX-512, -march=native), Release; and the sanitize preset (no -march,
      // -O1, ASan + UBSan + SPH_VALIDATE) on the same machine.
      {"pour",
       pinnedPour,
       {{"avx512/znver3/gcc12/release", 0xb051c4ced814fd58ull},
        {"sse2/other/gcc12/asan", 0x2d0a4b3bbb2af671ull}}},
      {"dam_break",
       pinnedDamBreak,
       {{"avx512/znver3/gcc12/release", 0xce7de10675bfa748ull},
        {"sse2/other/gcc12/asan", 0xd45f556a092a8b75ull}}},
  };
  return runs;
}

class PinnedHash : public ::testing::TestWithParam<std::size_t> {};

TEST_P(PinnedHash, MatchesTheValueWrittenHere) {
  const PinnedRun& r = pinnedRuns()[GetParam()];
  setThreadCount(2);
  const std::uint64_t two = r.run();
  setThreadCount(1);
  const std::uint64_t one = r.run();
  ASSERT_EQ(one, two) << "the thread count changed the result";
  char hex[32];
  std::snprintf(hex, sizeof hex, "0x%016" PRIx64 "ull", two);
  const std::string key = buildKey();
  for (const auto& [k, pinned] : r.hashes) {
    if (k != key) continue;
    EXPECT_EQ(two, pinned) << r.name << " on " << key << " now hashes to " << hex
                           << ": the results changed (see the comment above buildKey() before "
                              "updating the pinned value)";
    return;
  }
  GTEST_SKIP() << "no pinned hash for build " << key << "; this build gives {\"" << key << "\", "
               << hex << "} for " << r.name;
}

INSTANTIATE_TEST_SUITE_P(Runs, PinnedHash, ::testing::Range<std::size_t>(0, 2),
                         [](const ::testing::TestParamInfo<std::size_t>& p) {
                           return std::string(pinnedRuns()[p.param].name);
                         });

}  // namespace
}  // namespace sph
