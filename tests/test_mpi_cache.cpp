// The cache of a run on K processes (docs/scaling.md, "The cache is written by all ranks";
// docs/cache-format.md) when things go wrong or others read it: a rank killed at any moment or
// at any of its writes, a write that fails on one rank (a full disk), readers while the ranks
// write, and MPI-IO's own locks (ROMIO). The ranks are real processes started by Open MPI's
// mpirun; tests/KillAtWrite.cpp is the preload library that kills or fails them at a write.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/RainCache.h"
#include "job/distributed/mpi/MpiIoChoice.h"
#include "sim/InputError.h"
#include "tests/CacheTestSupport.h"
#include "tests/MpiTestSupport.h"

namespace sph {
namespace {

using test::runShell;
using test::mpi::Mpi;
using test::mpi::plain;
using test::mpi::ranks;
using test::mpi::romioComponent;

TEST_F(Mpi, AKilledRankLeavesEveryFinishedFrameReadable) {
  // kill -9 one rank in the middle of a long run: mpirun ends the others, and the cache keeps
  // the frames committed before, each readable and equal to the single process's.
  const std::string out = dir_ + "/killed.h5";
  auto r = runShell(killOneRankMidRun(out, "tail -1"));
  test::mpi::waitForStatusRecorder(out);
  EXPECT_NE(r.output.find("mpirun-exit"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("mpirun-exit 0"), std::string::npos) << r.output;
  const io::cache::CacheReader killed(out);
  const io::cache::CacheReader reference(reference_);
  ASSERT_GE(killed.frameCount(), 1u);
  for (std::size_t k = 0; k < killed.frameCount() && k < reference.frameCount(); ++k)
    EXPECT_TRUE(test::sameBits(reference.readFrame(k), killed.readFrame(k))) << "frame " << k;
}

TEST_F(Mpi, AKilledRankZeroLeavesACacheThatResumesOnOtherRanks) {
  // Rank 0 holds the lock, grows the file and writes the journal; killed mid-run, the cache
  // keeps its finished frames, and three ranks resume it.
  const std::string out = dir_ + "/killed0.h5";
  auto r = runShell(killOneRankMidRun(out, "head -1"));
  test::mpi::waitForStatusRecorder(out);
  EXPECT_EQ(r.output.find("mpirun-exit 0"), std::string::npos) << r.output;
  std::size_t kept = 0;
  double lastTime = 0;
  {
    const io::cache::CacheReader killed(out);
    const io::cache::CacheReader reference(reference_);
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
  const io::cache::CacheReader after(out);
  EXPECT_GE(after.frameCount(), kept + 1);
  for (std::size_t k = 0; k < after.frameCount(); ++k) EXPECT_GT(after.readFrame(k).size(), 0u);
}

TEST_F(Mpi, AKilledRankOfARainSceneLeavesItsFramesAndDropsReadable) {
  // The drops are written by rank 0 alone once the ranks have committed the frame: killed mid-
  // run, every finished frame reads back with its drops (the last one may have none yet), equal
  // to the single process's.
  std::ofstream(scene_) << test::mpi::rainScene(0.1);
  const std::string reference = dir_ + "/rain_plain.h5", out = dir_ + "/rain_killed.h5";
  auto a = runShell(plain(scene_, "-o '" + reference + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  auto r = runShell(killOneRankMidRun(out, "tail -1"));
  test::mpi::waitForStatusRecorder(out);
  EXPECT_EQ(r.output.find("mpirun-exit 0"), std::string::npos) << r.output;
  const io::cache::CacheReader killed(out), one(reference);
  // How many frames a loaded machine wrote before the kill varies.
  ASSERT_GE(killed.frameCount(), 1u);
  for (std::size_t k = 0; k < killed.frameCount(); ++k) {
    const Particles frame = killed.readFrame(k);
    const std::size_t drops = killed.summary().frames[k].rainDrops;
    if (k + 1 < killed.frameCount()) {
      EXPECT_EQ(drops, 3000u) << "frame " << k;
    }
    if (drops > 0) {
      EXPECT_EQ(io::cache::readRainFrame(killed, k).positions.size(), drops) << k;
    }
    if (k >= one.frameCount()) continue;
    EXPECT_TRUE(test::sameBits(one.readFrame(k), frame)) << "frame " << k;
    if (drops == 0) continue;
    EXPECT_EQ(io::cache::readRainFrame(one, k).generations,
              io::cache::readRainFrame(killed, k).generations)
        << "rain " << k;
  }
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
      test::mpi::waitForStatusRecorder(out);  // a resume now would meet it: it holds the lock
      if (!test::fileExists(out)) continue;   // killed before frame 0 was in: no cache
      {
        const io::cache::CacheReader killed(out);
        const io::cache::CacheReader reference(reference_);
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

TEST_F(Mpi, ARankKilledBeforeFrameZeroIsCommittedLeavesTheExistingCacheUntouched) {
  // Frame 0 is written by all ranks into PATH.partial, which rank 0 publishes as PATH once the
  // frame is committed (docs/scaling.md, "A distributed start"). A rank killed before any of its
  // writes to PATH.partial (from rank 0's creation of the file to the commit's last header
  // write) leaves the cache already at PATH byte for byte as it was, and the next run replaces
  // it with the single process's cache.
  long counts[2] = {0, 0};
  {
    const std::string only = "SPHSPLAT_COUNT_ONLY=.partial SPHSPLAT_WRITE_COUNT_FILE=" + dir_;
    auto r =
        runShell(twoShimmedRanks(dir_ + "/counted.h5", only + "/partial0", only + "/partial1"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (int k = 0; k < 2; ++k) {
      std::ifstream(dir_ + "/partial" + std::to_string(k)) >> counts[k];
      ASSERT_GT(counts[k], 0) << "rank " << k << " wrote nothing to the new cache's frame 0";
    }
  }
  const std::string out = dir_ + "/existing.h5";
  std::filesystem::copy_file(reference_, out);
  const std::string before = test::readFile(out);
  // Rank 0 at its first write (the file's creation) and its last (the commit's header), rank 1
  // in the middle of its part of the frame.
  const std::pair<int, long> kills[] = {{0, 1}, {0, counts[0]}, {1, (counts[1] + 1) / 2}};
  for (const auto& [victim, n] : kills) {
    {
      SCOPED_TRACE("rank " + std::to_string(victim) + " killed before its write " +
                   std::to_string(n) + " of " + std::to_string(counts[victim]) +
                   " to the .partial");
      const std::string kill =
          "SPHSPLAT_COUNT_ONLY=.partial SPHSPLAT_KILL_AT_WRITE=" + std::to_string(n);
      auto r = runShell(twoShimmedRanks(out, victim == 0 ? kill : "A=0", victim == 1 ? kill : "A=0",
                                        "", "--overwrite"));
      EXPECT_NE(r.exitCode, 0) << r.output;
      test::mpi::waitForStatusRecorder(out + ".partial");
      EXPECT_TRUE(test::readFile(out) == before) << "the existing cache changed";
    }
  }
  auto r = runShell(ranks(2, scene_, "--overwrite -o '" + out + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  test::expectSameCache(reference_, out);
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
        const io::cache::CacheReader reader(out);
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
    const io::cache::CacheReader done(out);
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

TEST(MpiIo, TheRanksWriteThroughRomioUnlessTheUserChose) {
  // OMPIO 4.1 hides a write the disk refused, ROMIO reports it (job/distributed/mpi/MpiIoChoice.h):
  // the ranks ask for ROMIO when a plug-in of it is installed, and leave a choice the user made
  // alone.
  const std::string dir = test::makeTempDir();
  for (const char* name : {"mca_io_ompio.so", "mca_io_romio321.so", "mca_io_romio341.so",
                           "mca_fs_romio999.so", "mca_io_romio.txt"})
    std::ofstream(dir + "/" + name) << "";
  EXPECT_EQ(job::distributed::mpi::findRomioComponent({"/nonexistent", dir}), "romio341");
  EXPECT_EQ(job::distributed::mpi::findRomioComponent({"/nonexistent"}), "");
  std::remove((dir + "/mca_io_romio321.so").c_str());
  std::remove((dir + "/mca_io_romio341.so").c_str());
  EXPECT_EQ(job::distributed::mpi::findRomioComponent({dir}), "");

  const std::string installed = romioComponent();  // what ompi_info lists
  EXPECT_EQ(
      job::distributed::mpi::findRomioComponent(job::distributed::mpi::componentDirectories()),
      installed);
  const char* users = std::getenv("OMPI_MCA_io");  // put back at the end
  const std::string before = users ? users : "";
  setenv("OMPI_MCA_io", "ompio", 1);
  EXPECT_EQ(job::distributed::mpi::preferRomio(), "as OMPI_MCA_io says (ompio)");
  EXPECT_STREQ(std::getenv("OMPI_MCA_io"), "ompio");
  unsetenv("OMPI_MCA_io");
  if (installed.empty()) {
    EXPECT_EQ(job::distributed::mpi::preferRomio(),
              "OMPIO (this Open MPI has no ROMIO component that loads)");
    EXPECT_EQ(std::getenv("OMPI_MCA_io"), nullptr);
  } else {
    EXPECT_EQ(job::distributed::mpi::preferRomio(), "ROMIO (" + installed + ")");
    EXPECT_EQ(std::getenv("OMPI_MCA_io"), installed);
  }
  if (users)
    setenv("OMPI_MCA_io", before.c_str(), 1);
  else
    unsetenv("OMPI_MCA_io");
}

TEST_F(Mpi, FramesWrittenTogetherThroughEitherMpiIoMatchOneProcess) {
  // ROMIO (MPICH's MPI-IO, the one the ranks ask Open MPI for) takes POSIX byte-range locks on
  // the cache while the ranks write a frame together; the run's own lock on the cache must not
  // overlap them (it did: a whole-file lock made rank 0's first ROMIO lock wait forever,
  // io/cache/CacheFileLock.cpp). OMPIO, where a user asks for it, writes the same frames.
  const std::string component = romioComponent();
  if (component.empty()) GTEST_SKIP() << "this Open MPI has no ROMIO component";
  for (const std::string chosen : {"", "ompio"}) {
    SCOPED_TRACE("OMPI_MCA_io=" + chosen);
    const std::string out = dir_ + "/io" + chosen + ".h5";
    // (The command quotes with ' only.)
    const auto r =
        runShell((chosen.empty() ? "" : "OMPI_MCA_io=" + chosen) + " timeout 120 sh -c \"" +
                 ranks(2, scene_, "-o '" + out + "'", "") + "\"");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string said =
        chosen.empty() ? "ROMIO (" + component + ")" : "as OMPI_MCA_io says (" + chosen + ")";
    EXPECT_NE(r.output.find(" ranks together (parallel HDF5, MPI-IO: " + said + ")"),
              std::string::npos)
        << r.output;
    test::expectSameCache(reference_, out);
  }
}

TEST_F(Mpi, AFullDiskOnOneRankStopsTheRunWithOneLineAndRecordsIt) {
  // One rank's N-th write of the cache fails with ENOSPC (tests/KillAtWrite.cpp), rank 0's (its
  // own frame 0, views and statuses too) or rank 1's: mpirun ends without hanging, the failing
  // rank says so in one line (no HDF5 error stack), the cache holds frames equal to the single
  // process's and its status says it stopped (recorded by rank 0, or by the recorder rank 0
  // starts when it cannot, job/distributed/StatusRecorder.h). Through ROMIO, which returns the
  // error on the failing rank, where the watch of job/distributed/mpi/FileErrorWatch.h ends a rank
  // left waiting in a collective call after it; Open MPI's OMPIO 4.1.4 hangs inside some collective
  // writes that fail on one rank (docs/scaling.md), so the ranks ask for ROMIO themselves: the runs
  // here leave OMPI_MCA_io unset, as a user's would be.
  if (romioComponent().empty()) GTEST_SKIP() << "this Open MPI has no ROMIO component";
  const std::string before = "timeout 60";
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
      // Rank 0 records why, or the recorder it started does once the ranks have ended
      // (job/distributed/StatusRecorder.h): a moment after mpirun returns.
      std::string status = "running";
      for (int wait = 0; wait < 100 && status.rfind("running", 0) == 0; ++wait) {
        if (wait > 0) usleep(200000);
        status = io::cache::CacheReader(out).summary().status;
      }
      EXPECT_EQ(status.rfind("stopped: ", 0), 0u) << status;
      EXPECT_NE(status.find("; last good frame "), std::string::npos) << status;
      const io::cache::CacheReader cache(out);
      const io::cache::CacheReader reference(reference_);
      for (std::size_t k = 0; k < cache.frameCount(); ++k)
        EXPECT_TRUE(test::sameBits(reference.readFrame(k), cache.readFrame(k))) << "frame " << k;
    }
  }
}

}  // namespace
}  // namespace sph
