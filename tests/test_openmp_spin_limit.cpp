// app/OpenMpSpinLimit.cpp: ctest starts this suite with neither OMP_WAIT_POLICY nor
// GOMP_SPINCOUNT set; main() relaunches it with the cap, as sphsplat's does, and libgomp must
// then stop spinning soon after a parallel region.
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <cstdlib>
#include <ctime>
#include <string>

#include "app/OpenMpSpinLimit.h"

namespace sph::app {
namespace {

double processCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

TEST(OpenMpSpinLimit, TheRelaunchedProcessCapsIdleSpinning) {
  ASSERT_EQ(std::getenv("OMP_WAIT_POLICY"), nullptr) << "run this suite through ctest";
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  ASSERT_NE(spin, nullptr) << "main() did not relaunch with the cap";
  EXPECT_EQ(std::string(spin), kOpenMpSpinCount);
  // What the cap is for: after a region, the idle threads must sleep within a fraction of a
  // millisecond. Uncapped, libgomp spun them for 6.5-10 ms of CPU per region on our 2-core EPYC.
  if (omp_get_max_threads() < 2) GTEST_SKIP() << "one OpenMP thread: nothing spins";
  double worst = 0;
  for (int round = 0; round < 3; ++round) {
    volatile double sink = 0;
#pragma omp parallel
    {
      double local = 0;
      for (int i = 0; i < 100000; ++i) local += i * 1e-9;
#pragma omp atomic
      sink += local;
    }
    const double before = processCpuSeconds();
    usleep(30000);
    const double spent = processCpuSeconds() - before;
    worst = std::max(worst, spent);
  }
  EXPECT_LT(worst, 0.003) << "CPU seconds the process burnt in a 30 ms sleep after a region";
}

TEST(OpenMpSpinLimit, TheUsersChoiceWins) {
  const std::string cap = std::getenv("GOMP_SPINCOUNT");
  EXPECT_FALSE(openMpSpinUnset());
  unsetenv("GOMP_SPINCOUNT");
  EXPECT_TRUE(openMpSpinUnset());
  setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
  EXPECT_FALSE(openMpSpinUnset());
  relaunchWithOpenMpSpinLimit(nullptr);  // must return without touching anything
  EXPECT_EQ(std::getenv("GOMP_SPINCOUNT"), nullptr);
  unsetenv("OMP_WAIT_POLICY");
  setenv("GOMP_SPINCOUNT", cap.c_str(), 1);
}

}  // namespace
}  // namespace sph::app

int main(int argc, char** argv) {
  sph::app::relaunchWithOpenMpSpinLimit(argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
