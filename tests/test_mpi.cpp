// A run on K processes (mpirun -np K; docs/scaling.md) writes the same cache as one process, bit
// for bit, for K = 1..4: every frame and every resume record. A resume may change K. Bad use is
// refused with one line and exit 2. Built and run in every build with MPI (the release preset
// when Open MPI is installed, SPHSPLAT_MPI=AUTO); the ranks are real processes started by Open
// MPI's mpirun (oversubscribed: this machine has 2 cores).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "io/CacheReader.h"
#include "io/Hdf5.h"
#include "sim/InputError.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::runShell;

// A dam break (the water runs along x across every slab face) with a nozzle pouring into the
// tank (emission on one rank, then migration): ~850 particles. The domain (the tank and its
// margin) is longest in y: 40 support-radius cells, so slabs are cut across the falling water.
std::string scene(double end) {
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

std::string plain(const std::string& sceneFile, const std::string& args) {
  return "OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + sceneFile +
         "' --threads 1 --quiet " + args;
}

std::string ranks(int k, const std::string& sceneFile, const std::string& args,
                  const std::string& mode = "--quiet") {
  return "OMP_WAIT_POLICY=PASSIVE mpirun --oversubscribe --allow-run-as-root -np " +
         std::to_string(k) + " " + test::sphsplatBinary() + " run '" + sceneFile +
         "' --threads 1 " + mode + " " + args;
}

// "romio321": Open MPI's ROMIO component (MPI-IO as MPICH has it), for OMPI_MCA_io; "" if this
// Open MPI has none.
std::string romioComponent() {
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
    ASSERT_GT(io::CacheReader(reference_).summary().frames.back().particles, 800u);
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
  // goes in front of mpirun (variables, `timeout N`).
  std::string twoShimmedRanks(const std::string& out, const std::string& env0,
                              const std::string& env1, const std::string& before = "") const {
    const std::string shim = SPHSPLAT_KILL_SHIM;
    const std::string rank =
        test::sphsplatBinary() + " run '" + scene_ + "' --threads 1 --quiet -o '" + out + "'";
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

TEST_F(Mpi, FramesAreBitIdenticalToOneProcessForOneToFourRanks) {
  for (int k = 1; k <= 4; ++k) {
    SCOPED_TRACE("K = " + std::to_string(k));
    const std::string out = dir_ + "/k" + std::to_string(k) + ".h5";
    auto r = runShell(ranks(k, scene_, "-o '" + out + "'", ""));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // With parallel HDF5 the ranks write each frame together, else rank 0 gathers and writes.
    const bool together =
        r.output.find(" ranks together (parallel HDF5, MPI-IO)") != std::string::npos;
    EXPECT_EQ(together, io::h5::haveParallel()) << r.output;
    test::expectSameCache(reference_, out);
    EXPECT_TRUE(test::fileExists(dir_ + "/k" + std::to_string(k) + ".xdmf"));
  }
}

TEST_F(Mpi, AResumeMayChangeTheNumberOfRanks) {
  const std::string out = dir_ + "/resumed.h5";
  // Ends on frame times (2 x 1/40 s): an --end between frames ends a frame early, alone too.
  auto a = runShell(ranks(2, scene_, "--end 0.05 -o '" + out + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  auto b = runShell(ranks(3, scene_, "--resume '" + out + "'"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  test::expectSameCache(reference_, out);
  // and back to one plain process
  const std::string out2 = dir_ + "/resumed_plain.h5";
  auto c = runShell(ranks(4, scene_, "--end 0.05 -o '" + out2 + "'"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  auto d = runShell(plain(scene_, "--resume '" + out2 + "'"));
  ASSERT_EQ(d.exitCode, 0) << d.output;
  test::expectSameCache(reference_, out2);
}

TEST_F(Mpi, TheExactCollisionPassGivesTheSameFramesOnThreeRanks) {
  // collision.method "exact" across ranks: each rank's ghosts hold its particles' partners, and
  // the nearest partner (ties: the lowest index) is the single process's. A range of 0.86
  // spacings: pairs squeezed closer than the lattice collide from the second frame on.
  const std::string exact = "--set collision.method=exact --set collision.range=0.0125 ";
  const std::string reference = dir_ + "/plain_exact.h5";
  auto r = runShell(plain(scene_, exact + "-o '" + reference + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  {  // the pass does change the run
    const io::CacheReader with(reference), without(reference_);
    ASSERT_EQ(with.frameCount(), without.frameCount());
    EXPECT_FALSE(test::sameBits(with.readFrame(2), without.readFrame(2)));
  }
  const std::string out = dir_ + "/exact_k3.h5";
  auto q = runShell(ranks(3, scene_, exact + "-o '" + out + "'"));
  ASSERT_EQ(q.exitCode, 0) << q.output;
  test::expectSameCache(reference, out);
}

TEST_F(Mpi, TheCdtCpuAndOctreePassesGiveTheSameFramesOnTwoAndThreeRanks) {
  // Passes that find pairs through structures of the whole fluid (the CDT's depth images, the
  // octree's leaves) run on the whole fluid gathered on every rank, in the single-process order.
  // The CDT with our improvements (4 depth layers, adaptive texel range) finds pairs from the
  // fourth frame on, octree from the second.
  for (const std::string method : {"cdt-cpu", "octree"}) {
    SCOPED_TRACE(method);
    const std::string set = "--set collision.method=" + method +
                            " --set collision.range=0.0125 --set collision.layers=4 "
                            "--set collision.adaptive_texel_range=true ";
    const std::string reference = dir_ + "/plain_" + method + ".h5";
    auto r = runShell(plain(scene_, set + "-o '" + reference + "'"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    {  // the pass does change the run
      const io::CacheReader with(reference), without(reference_);
      ASSERT_EQ(with.frameCount(), without.frameCount());
      const std::size_t last = with.frameCount() - 1;
      EXPECT_FALSE(test::sameBits(with.readFrame(last), without.readFrame(last)));
    }
    for (int k : {2, 3}) {
      const std::string out = dir_ + "/" + method + "_k" + std::to_string(k) + ".h5";
      auto q = runShell(ranks(k, scene_, set + "-o '" + out + "'"));
      ASSERT_EQ(q.exitCode, 0) << q.output;
      test::expectSameCache(reference, out);
    }
  }
}

TEST(MpiGuard, ABlowUpOnOneRankStopsAllWithTheSingleProcessMessage) {
  // A block thrown at 80 m/s along x (the domain's first longest axis): it leaves through the
  // last rank's slab, and every rank stops with exit 3 and the message one process gives.
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/blow.json";
  std::ofstream(file) << R"({"solver": {"spacing": 0.01, "gravity": [0,0,0], "speed_of_sound": 20},
    "domain": {"min": [-0.1,-0.1,-0.1], "max": [0.3,0.3,0.3]},
    "fluids": [{"min": [0,0,0], "max": [0.05,0.05,0.05], "velocity": [80,0,0]}]})";
  const auto one = runShell(plain(file, ""));
  const auto two = runShell(ranks(2, file, ""));
  ASSERT_EQ(one.exitCode, 3) << one.output;
  EXPECT_EQ(two.exitCode, 3) << two.output;
  auto message = [](const std::string& out) {
    const std::size_t at = out.find("numerical blow-up");
    return at == std::string::npos ? std::string() : out.substr(at, out.find('\n', at) - at);
  };
  ASSERT_NE(message(one.output), "") << one.output;
  EXPECT_EQ(message(two.output), message(one.output)) << two.output;
  EXPECT_NE(two.output.find("reproduce: mpirun -np 2 sphsplat run"), std::string::npos)
      << two.output;
}

TEST_F(Mpi, AKilledRankLeavesEveryFinishedFrameReadable) {
  // kill -9 one rank in the middle of a long run: mpirun ends the others, and the cache keeps
  // the frames committed before, each readable and equal to the single process's.
  const std::string out = dir_ + "/killed.h5";
  auto r = runShell(killOneRankMidRun(out, "tail -1"));
  EXPECT_NE(r.output.find("mpirun-exit"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("mpirun-exit 0"), std::string::npos) << r.output;
  const io::CacheReader killed(out);
  const io::CacheReader reference(reference_);
  ASSERT_GE(killed.frameCount(), 1u);
  for (std::size_t k = 0; k < killed.frameCount() && k < reference.frameCount(); ++k)
    EXPECT_TRUE(test::sameBits(reference.readFrame(k), killed.readFrame(k))) << "frame " << k;
}

TEST_F(Mpi, AKilledRankZeroLeavesACacheThatResumesOnOtherRanks) {
  // Rank 0 holds the lock, grows the file and writes the journal; killed mid-run, the cache
  // keeps its finished frames, and three ranks resume it.
  const std::string out = dir_ + "/killed0.h5";
  auto r = runShell(killOneRankMidRun(out, "head -1"));
  EXPECT_EQ(r.output.find("mpirun-exit 0"), std::string::npos) << r.output;
  std::size_t kept = 0;
  double lastTime = 0;
  {
    const io::CacheReader killed(out);
    const io::CacheReader reference(reference_);
    kept = killed.frameCount();
    ASSERT_GE(kept, 1u);
    lastTime = killed.summary().frames.back().time;
    for (std::size_t k = 0; k < kept; ++k) {
      const Particles frame = killed.readFrame(k);  // every finished frame reads back
      if (k < reference.frameCount()) {
        EXPECT_TRUE(test::sameBits(reference.readFrame(k), frame)) << "frame " << k;
      }
    }
  }
  char end[32];
  std::snprintf(end, sizeof end, "%.6f", lastTime + 0.05);
  auto resumed =
      runShell(ranks(3, scene_, std::string("--end ") + end + " --resume '" + out + "'"));
  ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
  const io::CacheReader after(out);
  EXPECT_GE(after.frameCount(), kept + 1);
  for (std::size_t k = 0; k < after.frameCount(); ++k) EXPECT_GT(after.readFrame(k).size(), 0u);
}

TEST_F(Mpi, ARankKilledAtAnyWriteOfTheCacheLeavesItReadableAndResumable) {
  // One rank is killed just before its N-th write to the cache (tests/KillAtWrite.cpp), at
  // writes spread over the whole run: its frames written together over MPI-IO and, for rank 0,
  // its own (frame 0, the views, the statuses, the journal, the growth). The cache then holds
  // frames equal to the single process's, and resuming it (on 3 ranks, or 1 plain process)
  // gives the single process's cache.
  long counts[2] = {0, 0};
  ASSERT_NO_FATAL_FAILURE(countWrites(counts));
  test::expectSameCache(reference_, dir_ + "/counted.h5");
  int resumed = 0;
  for (int victim = 0; victim < 2; ++victim) {
    for (int i = 1; i <= 4; ++i) {
      const long n = counts[victim] * i / 5;
      SCOPED_TRACE("rank " + std::to_string(victim) + " killed before write " + std::to_string(n) +
                   " of " + std::to_string(counts[victim]));
      const std::string out =
          dir_ + "/kill" + std::to_string(victim) + "_" + std::to_string(i) + ".h5";
      const std::string kill = "SPHSPLAT_KILL_AT_WRITE=" + std::to_string(n);
      auto r =
          runShell(twoShimmedRanks(out, victim == 0 ? kill : "A=0", victim == 1 ? kill : "A=0"));
      EXPECT_NE(r.exitCode, 0) << r.output;
      if (!test::fileExists(out)) continue;  // killed before frame 0 was in: no cache
      {
        const io::CacheReader killed(out);
        const io::CacheReader reference(reference_);
        for (std::size_t k = 0; k < killed.frameCount(); ++k)
          EXPECT_TRUE(test::sameBits(reference.readFrame(k), killed.readFrame(k))) << "frame " << k;
      }
      const std::string resume = "--resume '" + out + "'";
      auto c = runShell(++resumed % 2 ? ranks(3, scene_, resume) : plain(scene_, resume));
      ASSERT_EQ(c.exitCode, 0) << c.output;
      test::expectSameCache(reference_, out);
    }
  }
  EXPECT_GT(resumed, 4);
}

TEST_F(Mpi, ReadersDuringFramesWrittenTogetherNeverFail) {
  // Readers in a loop while two ranks write 20 frames together over MPI-IO, whose HDF5 driver
  // cuts the file to its end of allocation after each flush: sphsplat's reader (info, export,
  // render, view) never refuses the cache and every frame it reads is the finished cache's, bit
  // for bit; a plain HDF5 open (h5py, ParaView) may meet a commit under way but never a file
  // shorter than its superblock says ("truncated file").
  std::map<std::size_t, std::vector<Particles>> seen;  // frame -> each read of it
  std::vector<std::string> failures;
  std::map<std::string, int> plainFailures;
  long opens = 0, plainOpens = 0;
  std::string out;
  for (int run = 0; run < 4 && opens < 300; ++run) {
    out = dir_ + "/read" + std::to_string(run) + ".h5";
    const std::string command =
        ranks(2, scene_, "--end 0.05 --set output.fps=400 -o '" + out + "'") + " >/dev/null 2>&1";
    const pid_t pid = fork();
    if (pid == 0) {
      execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    ASSERT_GT(pid, 0);
    int status = 0;
    std::size_t lastFrames = 0;
    for (long round = 0; waitpid(pid, &status, WNOHANG) == 0; ++round) {
      if (!test::fileExists(out)) {  // still PATH.partial: frame 0 is not in yet
        usleep(1000);
        continue;
      }
      try {
        ++opens;
        const io::CacheReader reader(out);
        const std::size_t n = reader.frameCount();
        if (n < lastFrames)
          failures.push_back("frames went from " + std::to_string(lastFrames) + " to " +
                             std::to_string(n));
        lastFrames = n;
        if (!reader.summary().damagedFrame.empty())
          failures.push_back("damaged frame: " + reader.summary().damagedFrame);
        for (std::size_t k = round % 10 == 0 ? 0 : n - 1; k < n; ++k)
          seen[k].push_back(reader.readFrame(k));
      } catch (const InputError& e) {
        failures.push_back(e.what());
      }
      ++plainOpens;
      const std::string plain = test::plainOpenError(out);
      if (!plain.empty()) ++plainFailures[plain];
    }
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the run failed";
    const io::CacheReader done(out);
    ASSERT_EQ(done.frameCount(), 21u);
    for (auto& [k, reads] : seen) {
      for (const Particles& p : reads)
        if (!test::sameBits(done.readFrame(k), p)) failures.push_back("frame " + std::to_string(k));
    }
    seen.clear();
  }
  std::printf(
      "sphsplat reader: %ld opens, %zu failures; plain HDF5 open: %ld, %zu kinds of "
      "failure\n",
      opens, failures.size(), plainOpens, plainFailures.size());
  for (const auto& [what, n] : plainFailures) std::printf("  %d x %s\n", n, what.c_str());
  EXPECT_GE(opens, 200) << "too few opens to mean anything";
  for (std::size_t i = 0; i < failures.size() && i < 5; ++i) ADD_FAILURE() << failures[i];
  EXPECT_EQ(failures.size(), 0u);
  for (const auto& [what, n] : plainFailures)
    EXPECT_EQ(what.find("truncated file"), std::string::npos) << n << " x " << what;
}

TEST_F(Mpi, FramesWrittenTogetherThroughRomioMatchOneProcess) {
  // ROMIO (MPICH's MPI-IO, one of Open MPI's two) takes POSIX byte-range locks on the cache while
  // the ranks write a frame together; the run's own lock on the cache must not overlap them (it
  // did: a whole-file lock made rank 0's first ROMIO lock wait forever, io/CacheFileLock.cpp).
  const std::string component = romioComponent();
  if (component.empty()) GTEST_SKIP() << "this Open MPI has no ROMIO component";
  const std::string out = dir_ + "/romio.h5";
  // (The command quotes with ' only.)
  const auto r = runShell("OMPI_MCA_io=" + component + " timeout 120 sh -c \"" +
                          ranks(2, scene_, "-o '" + out + "'", "") + "\"");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find(" ranks together (parallel HDF5, MPI-IO)"), std::string::npos)
      << r.output;
  test::expectSameCache(reference_, out);
}

TEST_F(Mpi, AFullDiskOnOneRankStopsTheRunWithOneLineAndKeepsTheFrames) {
  // One rank's N-th write of the cache fails with ENOSPC (tests/KillAtWrite.cpp), rank 0's (its
  // own frame 0, views and statuses too) and rank 1's: mpirun
  // ends without hanging, the failing rank says so in one line (no HDF5 error stack), and the
  // cache holds frames equal to the single process's. Through ROMIO, which returns the error on
  // the failing rank, where the watch of mpi/FileErrorWatch.h ends a rank left waiting in a
  // collective call after it; Open MPI's OMPIO 4.1.4 itself hangs inside some collective writes
  // that fail on one rank (docs/scaling.md).
  const std::string component = romioComponent();
  if (component.empty()) GTEST_SKIP() << "this Open MPI has no ROMIO component";
  const std::string before = "OMPI_MCA_io=" + component + " timeout 60";
  long counts[2] = {0, 0};
  ASSERT_NO_FATAL_FAILURE(countWrites(counts, before, "SPHSPLAT_WRITE_LOG=" + dir_ + "/log0"));
  // Rank 0: its first three superblock writes (48 bytes) past the middle of the run, the last
  // word of a frame's flushes and of its close, where a failure left the ranks in calls that do
  // not match; then writes at 1/3 and 2/3 of the run. Rank 1: the same two.
  std::vector<long> points[2];
  {
    std::ifstream log(dir_ + "/log0");
    long n = 0, bytes = 0, offset = 0;
    while (log >> n >> bytes >> offset && points[0].size() < 3)
      if (bytes == 48 && n > counts[0] / 2) points[0].push_back(n);
    ASSERT_EQ(points[0].size(), 3u);
  }
  for (int victim = 0; victim < 2; ++victim)
    for (int i = 1; i <= 2; ++i) points[victim].push_back(counts[victim] * i / 3);
  for (int victim = 0; victim < 2; ++victim) {
    for (std::size_t i = 0; i < points[victim].size(); ++i) {
      const long n = points[victim][i];
      SCOPED_TRACE("rank " + std::to_string(victim) + " fails at write " + std::to_string(n) +
                   " of " + std::to_string(counts[victim]));
      const std::string out =
          dir_ + "/full" + std::to_string(victim) + "_" + std::to_string(i) + ".h5";
      const std::string fail = "SPHSPLAT_FAIL_AT_WRITE=" + std::to_string(n);
      auto r = runShell(
          twoShimmedRanks(out, victim == 0 ? fail : "A=0", victim == 1 ? fail : "A=0", before));
      EXPECT_NE(r.exitCode, 0) << r.output;
      EXPECT_NE(r.exitCode, 124) << "mpirun still ran after 60 s:\n" << r.output;
      std::size_t lines = 0;
      for (std::size_t at = r.output.find("sphsplat: "); at != std::string::npos;
           at = r.output.find("sphsplat: ", at + 1))
        ++lines;
      EXPECT_EQ(lines, 1u) << r.output;
      EXPECT_EQ(r.output.find("HDF5-DIAG"), std::string::npos) << r.output;
      EXPECT_EQ(r.output.find("time = "), std::string::npos) << r.output;
      if (!test::fileExists(out)) continue;  // failed before frame 0 was in: no cache
      const io::CacheReader cache(out);
      const io::CacheReader reference(reference_);
      for (std::size_t k = 0; k < cache.frameCount(); ++k)
        EXPECT_TRUE(test::sameBits(reference.readFrame(k), cache.readFrame(k))) << "frame " << k;
    }
  }
}

TEST(MpiMigration, ParticleCountAndMassAreConservedAsTheWaterCrossesFaces) {
  // A dam break in a closed tank that is longest along x, so the slabs are cut across x and the
  // collapsing column runs through every face; no emitter and no way out, so every frame must
  // hold exactly the starting particles, each once (the mass is one particle mass each, so it
  // is conserved with the count and the ids).
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/collapse.json";
  std::ofstream(file) << R"({"solver": {"spacing": 0.015, "cfl": 0.4, "end_time": 0.12},
    "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.15, 0.15, 0.06]}],
    "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.6, 0.2, 0.06]}],
    "output": {"fps": 50}})";
  for (int k = 2; k <= 4; ++k) {
    SCOPED_TRACE("K = " + std::to_string(k));
    const std::string out = dir + "/k" + std::to_string(k) + ".h5";
    auto r = runShell(ranks(k, file, "-o '" + out + "'", "--verbose"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // Particles did change rank after the first step's hand-out (the count over all ranks).
    const std::size_t at = r.output.find(" migrated between ranks");
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::size_t from = r.output.rfind(", ", at) + 2;
    EXPECT_GT(std::stoull(r.output.substr(from, at - from)), 10u) << r.output;
    const io::CacheReader cache(out);
    ASSERT_GE(cache.frameCount(), 6u);
    const Particles first = cache.readFrame(0);
    ASSERT_EQ(first.size(), 400u);
    float lastFront = 0;
    for (std::size_t f = 0; f < cache.frameCount(); ++f) {
      const Particles p = cache.readFrame(f);
      ASSERT_EQ(p.size(), first.size()) << "frame " << f;
      std::vector<int> seen(p.size(), 0);
      for (std::uint32_t id : p.id) {
        ASSERT_LT(id, seen.size()) << "frame " << f;
        ++seen[id];
      }
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(p.size()))
          << "frame " << f << ": a particle lost or duplicated";
      lastFront = *std::max_element(p.x.begin(), p.x.end());
    }
    EXPECT_GT(lastFront, 0.21f) << "the surge should have run 2 cell planes (0.03 m) along x";
  }
}

// A block thrown at 1 m/s through the domain's +x face, tolerating `maxLost` lost particles;
// returns the scene file written into `dir`.
std::string thrownBlockScene(const std::string& dir, int maxLost) {
  const std::string file = dir + "/thrown.json";
  std::ofstream(file) << R"({"solver": {"spacing": 0.01, "gravity": [0, 0, 0],
      "max_lost_particles": )"
                      << maxLost << R"(, "end_time": 0.25},
    "domain": {"min": [-0.1, -0.1, -0.1], "max": [0.3, 0.15, 0.15]},
    "fluids": [{"min": [0, 0, 0], "max": [0.1, 0.05, 0.05], "velocity": [1.0, 0, 0]}],
    "output": {"fps": 40}})";
  return file;
}

TEST(MpiLost, ParticlesLeavingTheDomainAreRemovedAndCountedAsByOneProcess) {
  // A block thrown at 1 m/s through the domain's +x face (the longest axis, so it leaves through
  // the last rank's slab): half of it leaves over some 70 steps, each particle removed and
  // counted as one process does (solver.max_lost_particles); the caches are bit-identical. Past
  // the tolerance every rank stops with the single process's message.
  const std::string dir = test::makeTempDir();
  const std::string file = thrownBlockScene(dir, 1000);
  auto line = [](const std::string& out, const std::string& words) {
    const std::size_t at = out.find(words);
    if (at == std::string::npos) return std::string();
    const std::size_t from = out.rfind('\n', at) + 1;
    return out.substr(from, out.find('\n', at) - from);
  };
  const std::string reference = dir + "/plain.h5";
  const auto one = runShell("OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + file +
                            "' --threads 1 -o '" + reference + "'");
  ASSERT_EQ(one.exitCode, 0) << one.output;
  const std::string removed = line(one.output, "particles left the domain and were removed");
  ASSERT_NE(removed.find("125 particles left"), std::string::npos) << one.output;
  for (int k = 2; k <= 3; ++k) {
    SCOPED_TRACE("K = " + std::to_string(k));
    const std::string out = dir + "/k" + std::to_string(k) + ".h5";
    const auto r = runShell(ranks(k, file, "-o '" + out + "'", ""));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(line(r.output, "particles left the domain and were removed"), removed);
    test::expectSameCache(reference, out);
  }
  // A tolerance of 60: the step that loses the 61st particle stops the run, exit 3.
  const std::string strict = " --set solver.max_lost_particles=60";
  const auto oneStrict = runShell(plain(file, strict));
  const auto threeStrict = runShell(ranks(3, file, strict));
  ASSERT_EQ(oneStrict.exitCode, 3) << oneStrict.output;
  EXPECT_EQ(threeStrict.exitCode, 3) << threeStrict.output;
  const std::string message = line(oneStrict.output, "more than solver.max_lost_particles = 60");
  ASSERT_NE(message, "") << oneStrict.output;
  EXPECT_EQ(line(threeStrict.output, "more than solver.max_lost_particles = 60"), message)
      << threeStrict.output;
}

TEST(MpiLost, AResumedRunCountsTheParticlesLostBeforeOnEveryRank) {
  // The thrown block of the test above with a tolerance of 100: a run to 0.225 s loses fewer,
  // the resume loses the 101st and stops as one process does (exit 3, the same message). The
  // particles leave through the last rank's slab, whose guard decides: it must count the
  // particles lost before the resume, which rank 0 read from the cache.
  const std::string dir = test::makeTempDir();
  const std::string file = thrownBlockScene(dir, 100);
  const auto one = runShell(plain(file, ""));
  ASSERT_EQ(one.exitCode, 3) << one.output;
  const std::string words = "more than solver.max_lost_particles = 100";
  auto line = [&](const std::string& out) {
    const std::size_t at = out.find(words);
    if (at == std::string::npos) return std::string();
    const std::size_t from = out.rfind('\n', at) + 1;
    return out.substr(from, out.find('\n', at) - from);
  };
  ASSERT_NE(line(one.output), "") << one.output;
  const std::string out = dir + "/part.h5";
  const auto first = runShell(ranks(2, file, "--end 0.225 -o '" + out + "'"));
  ASSERT_EQ(first.exitCode, 0) << first.output;
  {
    const io::CacheReader part(out);
    const auto [state, fluid] = part.readRestart(part.frameCount() - 1);
    ASSERT_GT(state.lostParticles, 0u) << "none lost before the resume";
    ASSERT_LE(state.lostParticles, 100u);
  }
  const auto resumed = runShell(ranks(3, file, "--resume '" + out + "'"));
  EXPECT_EQ(resumed.exitCode, 3) << resumed.output;
  EXPECT_EQ(line(resumed.output), line(one.output)) << resumed.output;
}

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
  const std::string plainPour = dir_ + "/plain_pour.h5", pourK3 = dir_ + "/pour_k3.h5";
  const auto a = runShell(plain(pour, kAccurate + "-o '" + plainPour + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  const auto b = runShell(ranks(3, pour, kAccurate + "-o '" + pourK3 + "'"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  test::expectSameCache(plainPour, pourK3);
}

TEST_F(MpiDfsph, AResumeMayChangeTheNumberOfRanks) {
  // The warm start of the resume record is gathered in the single-process order and handed out
  // with the particles again: from K = 2 to K = 3, and from K = 4 to a plain process.
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
    const io::CacheReader part(out2);
    const auto [state, fluid] = part.readRestart(part.frameCount() - 1);
    ASSERT_EQ(state.warmStart.density.size(), fluid.size());
    EXPECT_GT(*std::max_element(state.warmStart.density.begin(), state.warmStart.density.end()),
              0.0f);
  }
  auto d = runShell(plain(collapse_, kAccurate + "--resume '" + out2 + "'"));
  ASSERT_EQ(d.exitCode, 0) << d.output;
  test::expectSameCache(reference_, out2);
}

// Our one line, once (rank 0 tells; mpirun may add its own notice about the exit code).
void expectRefused(const test::CommandResult& r, const std::string& words) {
  EXPECT_EQ(r.exitCode, 2) << r.output;
  const std::size_t at = r.output.find("sphsplat: ");
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("sphsplat: ", at + 1), std::string::npos) << "told twice:\n" << r.output;
  EXPECT_NE(r.output.find(words), std::string::npos) << r.output;
}

TEST(MpiRefusals, ASceneTooSmallForTheRanks) {
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/scene.json";
  std::ofstream(file) << scene(0.05);
  expectRefused(runShell(ranks(12, file, "")), "too small for 12 processes");
}

TEST(MpiRefusals, TheGlCollisionPassAndTheRenderer) {
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/scene.json";
  std::ofstream(file) << scene(0.05);
  expectRefused(runShell(ranks(2, file, "--set collision.method=cdt-gl")),
                "runs on one process only");
}

TEST(MpiRefusals, TooManyThreadsIsToldOnceWithTheCoresARankMayUse) {
  // Every rank parses the same arguments; rank 0 alone tells, and the limit names what it counts
  // under mpirun: the cores this rank is bound to, not the machine's.
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/scene.json";
  std::ofstream(file) << scene(0.05);
  const auto r =
      runShell("OMP_WAIT_POLICY=PASSIVE mpirun --oversubscribe --allow-run-as-root -np 2 " +
               test::sphsplatBinary() + " run '" + file + "' --threads 100000");
  expectRefused(r, "cores mpirun binds this rank to), got '100000'");
  // A plain process says "here".
  const auto one = runShell(test::sphsplatBinary() + " run '" + file + "' --threads 100000");
  EXPECT_EQ(one.exitCode, 2) << one.output;
  EXPECT_NE(one.output.find(" here), got '100000'"), std::string::npos) << one.output;
}

TEST(MpiRefusals, AnOutputNoRankCanWrite) {
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/scene.json";
  std::ofstream(file) << scene(0.05);
  expectRefused(runShell(ranks(2, file, "-o /proc/no/such/dir/run.h5")), "run.h5");
}

}  // namespace
}  // namespace sph
