// A run on K processes (mpirun -np K; docs/scaling.md) writes the same cache as one process, bit
// for bit, for K = 1..4: every frame and every resume record. A resume may change K. Bad use is
// refused with one line and exit 2. Built and run in every build with MPI (the release and
// portable presets, SPHSPLAT_MPI=ON); the ranks are real processes started by Open MPI's mpirun
// (oversubscribed: this machine has 2 cores). The cache under kills, failed writes and readers:
// tests/test_mpi_cache.cpp; DFSPH's iterations: tests/test_mpi_dfsph.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

#include "io/cache/CacheReader.h"
#include "io/cache/Hdf5.h"
#include "io/cache/RainCache.h"
#include "io/scene/SceneLoader.h"
#include "sim/rain/RainStepper.h"
#include "tests/CacheTestSupport.h"
#include "tests/MpiTestSupport.h"

namespace sph {
namespace {

using test::runShell;
using test::mpi::Mpi;
using test::mpi::plain;
using test::mpi::ranks;
using test::mpi::scene;

TEST_F(Mpi, FramesAreBitIdenticalToOneProcessForOneToFourRanks) {
  for (int k = 1; k <= 4; ++k) {
    SCOPED_TRACE("K = " + std::to_string(k));
    const std::string out = dir_ + "/k" + std::to_string(k) + ".h5";
    auto r = runShell(ranks(k, scene_, "-o '" + out + "'", ""));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // With parallel HDF5 the ranks write each frame together, else rank 0 gathers and writes.
    const bool together =
        r.output.find(" ranks together (parallel HDF5, MPI-IO: ") != std::string::npos;
    EXPECT_EQ(together, io::cache::h5::haveParallel()) << r.output;
    test::expectSameCache(reference_, out);
    EXPECT_TRUE(test::fileExists(dir_ + "/k" + std::to_string(k) + ".xdmf"));
  }
}

// Settling (the scene's `settle`) steps every rank as one process steps, nothing released.
TEST_F(Mpi, ASettledStartIsTheSameOnTwoRanks) {
  const std::string one = dir_ + "/settled1.h5", two = dir_ + "/settled2.h5";
  auto a = runShell(plain(scene_, "--set settle=0.05 --end 0.05 -o '" + one + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  auto b = runShell(ranks(2, scene_, "--set settle=0.05 --end 0.05 -o '" + two + "'"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  test::expectSameCache(one, two);
}

TEST_F(Mpi, AResumeMayChangeTheNumberOfRanks) {
  const std::string out = dir_ + "/resumed.h5";
  // Ends on frame times (2 x 1/40 s).
  auto a = runShell(ranks(2, scene_, "--end 0.05 -o '" + out + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  auto b = runShell(ranks(3, scene_, "--resume '" + out + "'", ""));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  test::expectSameCache(reference_, out);
  // Each rank read only its slab of the last frame (job/distributed/DistributedResume.h): about a third.
  long long most = 0, all = 0;
  const std::size_t at = b.output.find("ranks read its slab of it: at most ");
  ASSERT_NE(at, std::string::npos) << b.output;
  ASSERT_EQ(std::sscanf(b.output.c_str() + at,
                        "ranks read its slab of it: at most %lld of its %lld", &most, &all),
            2);
  EXPECT_EQ(static_cast<std::size_t>(all),
            io::cache::CacheReader(out).summary().frames[2].particles);
  EXPECT_LT(most, all / 2) << b.output;
  // and back to one plain process
  const std::string out2 = dir_ + "/resumed_plain.h5";
  auto c = runShell(ranks(4, scene_, "--end 0.05 -o '" + out2 + "'"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  auto d = runShell(plain(scene_, "--resume '" + out2 + "'"));
  ASSERT_EQ(d.exitCode, 0) << d.output;
  test::expectSameCache(reference_, out2);
  // An end between frame times (0.06 s, between 0.05 and 0.075 s) leaves a last frame off the
  // frame grid: the resume goes on from the frame before and writes that one again, on the grid.
  const std::string out3 = dir_ + "/resumed_between.h5";
  auto e = runShell(ranks(3, scene_, "--end 0.06 -o '" + out3 + "'"));
  ASSERT_EQ(e.exitCode, 0) << e.output;
  EXPECT_EQ(io::cache::CacheReader(out3).summary().frames.back().time, 0.06);
  auto f = runShell(ranks(2, scene_, "--resume '" + out3 + "'", ""));
  ASSERT_EQ(f.exitCode, 0) << f.output;
  EXPECT_NE(f.output.find("is written again at t = 0.075 s"), std::string::npos) << f.output;
  test::expectSameCache(reference_, out3);
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
    const io::cache::CacheReader with(reference), without(reference_);
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
      const io::cache::CacheReader with(reference), without(reference_);
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
    const io::cache::CacheReader cache(out);
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
    const io::cache::CacheReader part(out);
    const auto [state, fluid] = part.readRestart(part.frameCount() - 1);
    ASSERT_GT(state.lostParticles, 0u) << "none lost before the resume";
    ASSERT_LE(state.lostParticles, 100u);
  }
  const auto resumed = runShell(ranks(3, file, "--resume '" + out + "'"));
  EXPECT_EQ(resumed.exitCode, 3) << resumed.output;
  EXPECT_EQ(line(resumed.output), line(one.output)) << resumed.output;
}

// A scene with rain on K processes: the fluid is written by all ranks together as any scene's,
// and rank 0 steps the drops with the union of the water cells the ranks' particles occupy (no
// particle is gathered) and writes them beside each frame: the fluid frames and the drops are
// the single process's, bit for bit, on 2 and 3 ranks and through a resume that changes K.
TEST(MpiRain, FramesAndDropsWrittenTogetherAreThoseOfOneProcess) {
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/rain.json", one = dir + "/one.h5";
  std::ofstream(file) << test::mpi::rainScene(0.1);
  const auto a = runShell(plain(file, "-o '" + one + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  {
    // The water stops drops in this scene: the stored drops are not those of a rain that meets
    // the solids alone (so the cells rank 0 is sent matter).
    const io::cache::CacheReader reader(one);
    scene::Scene sc = io::scene::loadScene(file);
    auto dry = rain::RainStepper::create(sc, rain::RainStepper::sceneAspect(sc));
    bool wet = false;
    for (std::size_t k = 0; k < reader.frameCount(); ++k) {
      ASSERT_GT(reader.summary().frames[k].rainDrops, 0u) << k;
      const io::cache::RainFrame stored = io::cache::readRainFrame(reader, k);
      dry->advanceTo(stored.time, Particles{});
      wet = wet || stored.generations != dry->system().generations();
    }
    EXPECT_TRUE(wet);
  }
  for (int k = 2; k <= 3; ++k) {
    SCOPED_TRACE("K = " + std::to_string(k));
    const std::string out = dir + "/k" + std::to_string(k) + ".h5";
    const auto r = runShell(ranks(k, file, "-o '" + out + "'", "--verbose"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    if (io::cache::h5::haveParallel()) {
      EXPECT_NE(r.output.find("frames written by all " + std::to_string(k) + " ranks together"),
                std::string::npos)
          << r.output;
      EXPECT_NE(r.output.find("bytes of water cells received a frame on rank 0"), std::string::npos)
          << r.output;
    }
    test::expectSameCache(one, out);
    // `info` tells the drops as it does of the single process's cache.
    const auto info = [](const std::string& cache) {
      const auto i = runShell(test::sphsplatBinary() + " info '" + cache + "'");
      EXPECT_EQ(i.exitCode, 0) << i.output;
      const std::size_t at = i.output.find("  rain ");
      return at == std::string::npos ? std::string("no rain line: " + i.output)
                                     : i.output.substr(at, i.output.find('\n', at) - at);
    };
    EXPECT_EQ(info(out), info(one));
  }
  // Stopped at 0.05 s on 3 ranks, resumed on 2: the drops continue from the stored ones.
  const std::string resumed = dir + "/resumed.h5";
  const auto b = runShell(ranks(3, file, "--end 0.05 -o '" + resumed + "'"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  const auto c = runShell(ranks(2, file, "--resume '" + resumed + "'"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  test::expectSameCache(one, resumed);
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

TEST(MpiRefusals, AResumeOfAnotherSceneIsToldOnce) {
  // Rank 0 checks a resume against the scene once the ranks run in lockstep: its refusal is one
  // line and exit 2 on every rank, not one line a rank and an abort.
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/scene.json", out = dir + "/run.h5";
  std::ofstream(file) << scene(0.05);
  const auto first = runShell(ranks(2, file, "-o '" + out + "'"));
  ASSERT_EQ(first.exitCode, 0) << first.output;
  const auto r =
      runShell(ranks(2, file, "--end 0.1 --set solver.viscosity=0.002 --resume '" + out + "'"));
  expectRefused(r, "not the scene the cache");
  EXPECT_EQ(r.output.find("MPI_ABORT"), std::string::npos) << r.output;
}

TEST(MpiRefusals, AnOutputNoRankCanWrite) {
  const std::string dir = test::makeTempDir();
  const std::string file = dir + "/scene.json";
  std::ofstream(file) << scene(0.05);
  expectRefused(runShell(ranks(2, file, "-o /proc/no/such/dir/run.h5")), "run.h5");
}

}  // namespace
}  // namespace sph
