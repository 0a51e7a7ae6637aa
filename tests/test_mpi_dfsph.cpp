// DFSPH (solver.pressure "dfsph", the accurate preset) on K processes (mpirun -np K;
// docs/scaling.md): the same cache as one process, bit for bit, through its Jacobi iterations,
// their warm start and a resume that changes K. The rest of the MPI suite: tests/test_mpi.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "io/cache/CacheReader.h"
#include "tests/CacheTestSupport.h"
#include "tests/MpiTestSupport.h"

namespace sph {
namespace {

using test::runShell;
using test::mpi::plain;
using test::mpi::ranks;
using test::mpi::scene;

// DFSPH (solver.pressure "dfsph", the accurate preset) on K processes: its Jacobi iterations read
// the neighbours' velocities of the iteration before, so the ghosts' velocities are sent again
// before every source pass; the warm start travels with the particles and into the resume
// record; the error means that stop the iterations are exact global sums. Every frame and resume
// record (the warm start included) is the single process's, bit for bit.
class MpiDfsph : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::makeTempDir();
    // A dam break in a tank longest along x: the slabs are cut across x, the rows of grid cells
    // the DFSPH pairs are stored by cross the faces, and the surge runs through every face.
    collapse_ = dir_ + "/collapse.json";
    std::ofstream(collapse_) << R"({"solver": {"spacing": 0.015, "end_time": 0.12},
      "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.15, 0.15, 0.06]}],
      "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.6, 0.2, 0.06]}],
      "output": {"fps": 50}})";
    reference_ = dir_ + "/plain.h5";
    const auto r =
        runShell("OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + collapse_ +
                 "' --threads 1 --verbose " + kAccurate + "-o '" + reference_ + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // The solvers iterate (so the refreshes matter): at least two density iterations a step.
    const std::size_t at = r.output.find("dfsph: ");
    ASSERT_NE(at, std::string::npos) << r.output;
    EXPECT_GE(std::stod(r.output.substr(at + 7)), 2.0) << r.output;
  }
  static inline const std::string kAccurate = "--set quality=accurate ";
  // The scene `file` with the accurate preset on one process and on `k` ranks: the same cache.
  void expectRanksMatchOneProcess(const std::string& file, int k, const std::string& name) {
    const std::string one = dir_ + "/" + name + "_1.h5", many = dir_ + "/" + name + "_k.h5";
    const auto a = runShell(plain(file, kAccurate + "-o '" + one + "'"));
    ASSERT_EQ(a.exitCode, 0) << a.output;
    const auto b = runShell(ranks(k, file, kAccurate + "-o '" + many + "'"));
    ASSERT_EQ(b.exitCode, 0) << b.output;
    test::expectSameCache(one, many);
  }
  std::string dir_, collapse_, reference_;
};

TEST_F(MpiDfsph, FramesAreBitIdenticalToOneProcessForOneToFourRanks) {
  for (int k = 1; k <= 4; ++k) {
    SCOPED_TRACE("K = " + std::to_string(k));
    const std::string out = dir_ + "/k" + std::to_string(k) + ".h5";
    const auto r = runShell(ranks(k, collapse_, kAccurate + "-o '" + out + "'", "--verbose"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    test::expectSameCache(reference_, out);
    if (k > 1) {  // the refreshes ran: one before every source pass
      EXPECT_NE(r.output.find("DFSPH ghost velocity refreshes"), std::string::npos) << r.output;
    }
  }
  // The pour (slabs across y, a nozzle on one rank): emitted particles join with a zero warm
  // start wherever they are first sorted, and migrate with theirs.
  const std::string pour = dir_ + "/pour.json";
  std::ofstream(pour) << scene(0.1);
  expectRanksMatchOneProcess(pour, 3, "pour");
}

TEST_F(MpiDfsph, TheMomentumIterationsAreThoseOfOneProcess) {
  // From the first iteration (density_momentum_after 0), each constant-density iteration reads
  // its own last stiffness and this step's sum, the ghosts' too: with walls that hold pressure
  // (the ghosts' stiffness sent by their owners) and with walls that hold none (computed where
  // they are). The projected solve too, which reads the whole sum, warm start included, with
  // divergence steps of no iteration (the decision taken from the global error).
  struct Variant {
    const char* label;
    const char* set;
  };
  for (const Variant& v : {Variant{"extrapolated", "--set solver.wall_pressure=extrapolated "},
                           Variant{"none", "--set solver.wall_pressure=none "},
                           Variant{"projected",
                                   "--set solver.density_solve=projected "
                                   "--set solver.density_warm_start=0.8 "
                                   "--set solver.min_divergence_iterations=0 "}}) {
    SCOPED_TRACE(v.label);
    const std::string set = kAccurate + "--set solver.density_momentum_after=0 " + v.set;
    const std::string one = dir_ + "/momentum_" + v.label + "_1.h5",
                      many = dir_ + "/momentum_" + v.label + "_3.h5";
    const auto a = runShell(plain(collapse_, set + "-o '" + one + "'"));
    ASSERT_EQ(a.exitCode, 0) << a.output;
    const auto b = runShell(ranks(3, collapse_, set + "-o '" + many + "'"));
    ASSERT_EQ(b.exitCode, 0) << b.output;
    test::expectSameCache(one, many);
  }
}

TEST_F(MpiDfsph, TheWarmStartForWaterAtRestIsDecidedForTheWholeFluid) {
  // A pool at rest stepped at 1.5 ms, far under gravity's bound, with a block falling into one end:
  // the constant-density solver's warm start is lowered while most of the fluid is slow (Dfsph.cpp,
  // densityWarmShare()), a count over every rank. The rank that holds the falling block is mostly
  // fast, the others slow: each must take the whole fluid's decision.
  const std::string pool = dir_ + "/restpool.json";
  std::ofstream(pool) << R"({"solver": {"spacing": 0.015, "end_time": 0.1, "max_time_step": 0.0015},
    "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.3, 0.15, 0.06]},
               {"type": "box", "min": [0, 0.2, 0], "max": [0.09, 0.3, 0.06],
                "velocity": [0, -2, 0]}],
    "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.3, 0.35, 0.06]}],
    "output": {"fps": 50}})";
  expectRanksMatchOneProcess(pool, 3, "restpool");
}

TEST_F(MpiDfsph, AGatheredFrameZeroHasNoWarmStartYet) {
  // A scene with rain, frame 0 included: gathered to rank 0 in a build with the serial HDF5
  // library, where before the first exchange DFSPH's warm start exists on no rank and the gather
  // must not read it (it read past empty arrays); with parallel HDF5 written together, the drops
  // stepped on rank 0 with the ranks' water cells (MpiRain below).
  const std::string rain = dir_ + "/rain.json";
  std::ofstream(rain) << R"({"solver": {"spacing": 0.015, "end_time": 0.06},
    "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.15, 0.15, 0.06]}],
    "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.6, 0.2, 0.06]}],
    "camera": {"position": [0.3, 0.3, 0.8], "target": [0.3, 0.1, 0.03], "fov": 40},
    "rain": {"count": 300, "near": 0.05, "far": 0.8, "fall_speed": 3, "seed": 7},
    "output": {"fps": 50}})";
  expectRanksMatchOneProcess(rain, 2, "rain");
}

TEST_F(MpiDfsph, AResumeMayChangeTheNumberOfRanks) {
  // The warm start of the resume record is written in the single-process order, and each rank of
  // the resume reads its slab's part of it with the particles: from K = 2 to K = 3, and from K = 4
  // to a plain process.
  const std::string out = dir_ + "/resumed.h5";
  auto a = runShell(ranks(2, collapse_, kAccurate + "--end 0.06 -o '" + out + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  auto b = runShell(ranks(3, collapse_, kAccurate + "--resume '" + out + "'"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  test::expectSameCache(reference_, out);
  const std::string out2 = dir_ + "/resumed_plain.h5";
  auto c = runShell(ranks(4, collapse_, kAccurate + "--end 0.06 -o '" + out2 + "'"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  {  // the record holds a warm start (the run had one to carry)
    const io::cache::CacheReader part(out2);
    const auto [state, fluid] = part.readRestart(part.frameCount() - 1);
    ASSERT_EQ(state.warmStart.density.size(), fluid.size());
    EXPECT_GT(*std::max_element(state.warmStart.density.begin(), state.warmStart.density.end()),
              0.0f);
  }
  auto d = runShell(plain(collapse_, kAccurate + "--resume '" + out2 + "'"));
  ASSERT_EQ(d.exitCode, 0) << d.output;
  test::expectSameCache(reference_, out2);
}

}  // namespace
}  // namespace sph
