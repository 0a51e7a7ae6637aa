// app/OpenMpSpinLimit: sphsplat starts itself again with libgomp's idle spinning capped unless
// the user chose (OMP_WAIT_POLICY or GOMP_SPINCOUNT), and says so in `run --verbose`. The suite
// checks the binary's report, then what the cap it reports is for: main() relaunches this test
// process with the GOMP_SPINCOUNT the binary runs with (ctest starts it with neither variable
// set), and libgomp must then stop spinning soon after a parallel region.
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <cstdlib>
#include <ctime>
#include <regex>
#include <string>

#include "tests/TestSupport.h"

namespace sph {
namespace {

std::string verboseRun(const std::string& environment) {
  const std::string scene = test::writeTempFile(R"({"solver": {"spacing": 0.05, "end_time": 0.001},
        "fluids": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]})");
  return test::runShell("env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT " + environment + " " +
                        test::sphsplatCommand() + " run " + scene + " --verbose --threads 2")
      .output;
}

// The GOMP_SPINCOUNT sphsplat runs with when the user set nothing ("" if none).
std::string binarysSpinCount() {
  std::smatch m;
  const std::string out = verboseRun("");
  return std::regex_search(out, m, std::regex("idle spinning capped \\(GOMP_SPINCOUNT=([0-9]+)"))
             ? m[1].str()
             : "";
}

TEST(OpenMpSpinLimit, TheBinaryCapsIdleSpinningUnlessTheUserChose) {
  EXPECT_NE(binarysSpinCount(), "") << verboseRun("");
  const std::string passive = verboseRun("OMP_WAIT_POLICY=PASSIVE");
  EXPECT_NE(passive.find("OpenMP: 2 threads, idle waiting as set (OMP_WAIT_POLICY=PASSIVE)"),
            std::string::npos)
      << passive;
  const std::string spin = verboseRun("GOMP_SPINCOUNT=5");
  EXPECT_NE(spin.find("idle waiting as set (GOMP_SPINCOUNT=5)"), std::string::npos) << spin;
}

double processCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

TEST(OpenMpSpinLimit, TheCapStopsIdleThreadsSpinningAfterARegion) {
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  ASSERT_NE(spin, nullptr) << "main() did not relaunch with the binary's cap";
  // After a region the idle threads must sleep within a fraction of a millisecond. Uncapped,
  // libgomp spun them for 6.5-10 ms of CPU per region on our 2-core EPYC.
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

}  // namespace
}  // namespace sph

int main(int argc, char** argv) {
  // libgomp reads GOMP_SPINCOUNT when it loads: start again with the binary's value set.
  if (!std::getenv("GOMP_SPINCOUNT") && !std::getenv("OMP_WAIT_POLICY")) {
    const std::string cap = sph::binarysSpinCount();
    sph::test::discardTempFiles();  // exec ends this image: its listener would never remove them
    if (!cap.empty() && setenv("GOMP_SPINCOUNT", cap.c_str(), 1) == 0)
      execv("/proc/self/exe", argv);
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
