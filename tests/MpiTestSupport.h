// Shared by the MPI suites (tests/test_mpi.cpp, tests/test_mpi_cache.cpp): the scene they run,
// the commands of a plain run and of K ranks (Open MPI's mpirun, oversubscribed: this machine
// has 2 cores), and the fixture that writes the single process's reference cache.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "io/cache/CacheReader.h"
#include "tests/CacheTestSupport.h"

namespace sph::test::mpi {

// A dam break (the water runs along x across every slab face) with a nozzle pouring into the
// tank (emission on one rank, then migration): ~850 particles. The domain (the tank and its
// margin) is longest in y: 40 support-radius cells, so slabs are cut across the falling water.
inline std::string scene(double end) {
  return R"({
  "name": "mpi_dam_pour",
  "solver": {"spacing": 0.0146, "support": 2.0, "rest_density": 1000, "eos": "tait",
             "cfl": 0.4, "gravity": [0, -9.81, 0], "end_time": )" +
         std::to_string(end) + R"(},
  "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.146, 0.292, 0.0584]}],
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.584, 0.438, 0.0584]}],
  "emitters": [{"type": "nozzle", "position": [0.45, 0.35, 0.03], "direction": [0, -1, 0],
                "radius": 0.02, "speed": 0.8, "start": 0, "stop": 1}],
  "camera": {"position": [0.3, 0.3, 0.8], "target": [0.3, 0.1, 0.03], "fov": 40},
  "output": {"fps": 40}
})";
}

// The same with rain (its drops land in the water and are stored beside the frames, /Rain#N):
// rank 0 steps them with the water cells every rank's particles occupy.
inline std::string rainScene(double end) {
  std::string s = scene(end);
  const std::string output = R"("output": )";
  // The paper's placement ("occlusion": "none"): the camera faces the tank's front wall, which
  // hides the water, so drops kept only where the eye sees them would never reach it, and the
  // water cells rank 0 is sent would stop none.
  s.insert(s.find(output), R"("rain": {"count": 3000, "near": 0.05, "far": 0.8, "fall_speed": 3,
           "seed": 7, "occlusion": "none"},
  )");
  return s;
}

inline std::string plain(const std::string& sceneFile, const std::string& args) {
  return "OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + sceneFile +
         "' --threads 1 --quiet " + args;
}

inline std::string ranks(int k, const std::string& sceneFile, const std::string& args,
                         const std::string& mode = "--quiet") {
  return "OMP_WAIT_POLICY=PASSIVE mpirun --oversubscribe --allow-run-as-root -np " +
         std::to_string(k) + " " + test::sphsplatBinary() + " run '" + sceneFile +
         "' --threads 1 " + mode + " " + args;
}

// Waits (at most 70 s) until no status recorder for the cache `path` runs
// (job/distributed/StatusRecorder.h): rank 0 of a run stopped in a frame its ranks wrote together
// starts one, which records the status a moment after mpirun returns, holding the cache's lock
// while it writes.
inline void waitForStatusRecorder(const std::string& path) {
  const std::string argument = std::string("--record-stopped-run") + '\0' + path + '\0';
  const auto runs = [&] {
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator("/proc", error)) {
      std::ifstream file(entry.path() / "cmdline", std::ios::binary);
      const std::string line((std::istreambuf_iterator<char>(file)), {});
      if (line.find(argument) != std::string::npos) return true;
    }
    return false;
  };
  for (int i = 0; i < 700 && runs(); ++i) usleep(100000);
}

// "romio321": Open MPI's ROMIO component (MPI-IO as MPICH has it), for OMPI_MCA_io; "" if this
// Open MPI has none.
inline std::string romioComponent() {
  const auto info = runShell("ompi_info 2>/dev/null | grep -o 'MCA io: romio[0-9]*'");
  const std::size_t at = info.output.find("romio");
  if (at == std::string::npos) return "";
  return info.output.substr(at, info.output.find_first_of("\n ", at) - at);
}

class Mpi : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::makeTempDir();
    scene_ = dir_ + "/scene.json";
    std::ofstream(scene_) << scene(0.1);
    reference_ = dir_ + "/plain.h5";
    auto r = runShell(plain(scene_, "-o '" + reference_ + "'"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    ASSERT_GT(io::cache::CacheReader(reference_).summary().frames.back().particles, 800u);
  }
  // A shell script: a 2-rank run to 5 s, one rank of it (`pick` of mpirun's children: "head -1"
  // or "tail -1") killed with SIGKILL 3 s after the cache appears; prints "mpirun-exit CODE".
  std::string killOneRankMidRun(const std::string& out, const std::string& pick) const {
    return ranks(2, scene_, "--end 5 -o '" + out + "'") + " & M=$!; " +
           "for i in $(seq 600); do [ -f '" + out + "' ] && break; sleep 0.1; done; sleep 3; " +
           "kill -9 $(pgrep -P $M | " + pick + "); wait $M; echo mpirun-exit $?";
  }
  // Two ranks of the scene writing `out`, each under the preload library of the crash tests
  // (tests/KillAtWrite.cpp) with its own variables (`env0`, `env1`: "VAR=VALUE ..."); `before`
  // goes in front of mpirun (variables, `timeout N`), `args` after the run's own.
  std::string twoShimmedRanks(const std::string& out, const std::string& env0,
                              const std::string& env1, const std::string& before = "",
                              const std::string& args = "") const {
    const std::string shim = SPHSPLAT_KILL_SHIM;
    const std::string rank = test::sphsplatBinary() + " run '" + scene_ +
                             "' --threads 1 --quiet -o '" + out + "' " + args;
    return "OMP_WAIT_POLICY=PASSIVE " + before +
           " mpirun --oversubscribe --allow-run-as-root -np 1 env " + env0 + " LD_PRELOAD='" +
           shim + "' " + rank + " : -np 1 env " + env1 + " LD_PRELOAD='" + shim + "' " + rank;
  }
  // Each rank's writes to the cache in a clean run of twoShimmedRanks into dir_/counted.h5
  // (`env0`: more variables for rank 0).
  void countWrites(long counts[2], const std::string& before = "",
                   const std::string& env0 = "") const {
    auto r = runShell(twoShimmedRanks(dir_ + "/counted.h5",
                                      "SPHSPLAT_WRITE_COUNT_FILE=" + dir_ + "/count0 " + env0,
                                      "SPHSPLAT_WRITE_COUNT_FILE=" + dir_ + "/count1", before));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (int k = 0; k < 2; ++k) {
      std::ifstream(dir_ + "/count" + std::to_string(k)) >> counts[k];
      ASSERT_GT(counts[k], 0) << "rank " << k;
    }
  }
  std::string dir_, scene_, reference_;
};

}  // namespace sph::test::mpi
