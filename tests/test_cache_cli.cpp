// The cache commands as a user meets them: `run --output` with its summary, `info`, a report that
// cannot be written, closed standard streams, a blow-up keeping its finished frames and naming the
// last good one, Ctrl-C stopping with a resumable cache, and a full disk stopping the run with its
// frames kept. Where the commands may write is test_cache_cli_paths; bad and damaged caches are
// test_cache_cli_damage.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "io/cache/CacheReader.h"
#include "tests/CacheCliSuite.h"

namespace sph {
namespace {

using test::CacheCli;
using test::lineCount;
using test::readFile;
using test::runShell;
using test::sphsplat;

TEST_F(CacheCli, RunWritesTheCacheAndSaysWhere) {
  ASSERT_EQ(runOutput_.exitCode, 0) << runOutput_.output;
  EXPECT_NE(runOutput_.output.find("cache: " + cache_ + " (+ " + dir_ +
                                   "/tiny.xdmf for ParaView): 11 frames"),
            std::string::npos)
      << runOutput_.output;
  EXPECT_NE(runOutput_.output.find("; frame datasets "), std::string::npos);
  EXPECT_NE(runOutput_.output.find(" bytes per particle per frame; writing took "),
            std::string::npos);
  EXPECT_TRUE(test::fileExists(dir_ + "/tiny.xdmf"));
  EXPECT_FALSE(test::fileExists(cache_ + ".partial"));
  const auto help = runShell(sphsplat("run --help"));
  for (const char* flag : {"--output", "--overwrite", "--no-compress", "--resume"}) {
    EXPECT_NE(help.output.find(flag), std::string::npos) << flag;
  }
}

// The scene's --set edits, stored a line each, are said on the scene's line as given.
TEST_F(CacheCli, InfoSaysEveryOverrideOnTheScenesLine) {
  const std::string path = dir_ + "/two_sets.h5";
  const auto run = runShell(sphsplat("run '" + scene_ + "' --threads 1 --set solver.cfl=0.3 " +
                                     "--set output.compression=2 -o '" + path + "'"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const auto r = runShell(sphsplat("info '" + path + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("scene      tiny (" + scene_ +
                          "), --set solver.cfl=0.3 --set output.compression=2\n"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("deflate 2 + shuffle"), std::string::npos) << r.output;
}

TEST_F(CacheCli, InfoDescribesTheCache) {
  const auto r = runShell(sphsplat("info '" + cache_ + "' --frames"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const std::string& expected : std::vector<std::string>{
           cache_ + ": sphsplat cache (format 1", "scene      tiny (" + scene_ + ")",
           "status     finished at t = 0.1 s",
           "frames     11 (Step#0 - Step#10), t = 0 - 0.1 s at 100 frames/s",
           "particles  96 - 98 fluid per frame (98 in the last), ",
           "fields     x y z vx vy vz rho p id (float32, id uint32), deflate 1 + shuffle",
           "resume     11 frames have a resume record", "solver     ", "spacing 0.025",
           "rendered   none", "ParaView   paraview " + dir_ + "/tiny.xdmf",
           "bytes per particle per frame"}) {
    EXPECT_NE(r.output.find(expected), std::string::npos) << "missing: " << expected << "\n"
                                                          << r.output;
  }
}

// A report that cannot be written is a failed command, exit 2 as for any write that failed (info
// > /dev/full exited 0). Standard error stays with the test: only standard output is full.
TEST_F(CacheCli, AFullStandardOutputFailsTheCommandWithOneLine) {
  auto r = runShell("(" + sphsplat("info '" + cache_ + "' --frames") + " > /dev/full)");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(r.output, "sphsplat: cannot write to standard output (No space left on device)\n");
  r = runShell("(" + sphsplat("export '" + cache_ + "' --frames 3 --format csv -o -") +
               " > /dev/full)");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(r.output, "sphsplat: standard output: cannot write the export\n");
}

// Started with its output and error streams closed, a run gives descriptors 1 and 2 to
// /dev/null, not to the first files it opens (its lock and its cache, where progress lines would
// then be written), and its cache is the cache of a run with them open.
TEST_F(CacheCli, ClosedStandardStreamsAreNotTheCache) {
  const std::string cache = dir_ + "/closed.h5";
  const std::string run = sphsplat("run '" + scene_ + "' --threads 1 --end 5 -o '" + cache + "'");
  const auto r = runShell("(" + run + " >&- 2>&- & p=$!; for i in $(seq 1000); do [ -e '" +
                          cache + ".partial' ] || [ -e '" + cache +
                          "' ] && break; sleep 0.01; done; readlink /proc/$p/fd/1 /proc/$p/fd/2; "
                          "kill $p; wait $p)");
  EXPECT_EQ(r.output, "/dev/null\n/dev/null\n");
  const std::string whole = dir_ + "/closed_whole.h5";
  const auto w = runShell("(" + sphsplat("run '" + scene_ + "' --threads 1 -o '" + whole + "'") +
                          " >&- 2>&-)");
  EXPECT_EQ(w.exitCode, 0) << w.output;
  test::expectSameCache(cache_, whole);
}

TEST_F(CacheCli, BlowUpKeepsTheFinishedFramesAndNamesTheLastGoodOne) {
  // A block flung sideways leaves the domain after about 0.3 s: the guard stops the run.
  const std::string scene = dir_ + "/fling.json";
  std::ofstream(scene)
      << R"({"solver": {"spacing": 0.025, "end_time": 1}, "domain": {"min": [-1, -1, -1], "max": [1, 1, 1]},
    "fluids": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.1], "velocity": [3, 0, 0]}], "output": {"fps": 100}})";
  const std::string cache = dir_ + "/fling.h5";
  const auto r = runShell(sphsplat("run '" + scene + "' --threads 1 --quiet -o '" + cache + "'"));
  ASSERT_EQ(r.exitCode, 3) << r.output;
  const io::cache::CacheReader reader(cache);
  const std::size_t frames = reader.frameCount();
  ASSERT_GT(frames, 10u);
  const std::string last = std::to_string(frames - 1);
  EXPECT_NE(r.output.find("the cache " + cache + " keeps frames 0-" + last), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("the last good frame is " + last + " (t = "), std::string::npos)
      << r.output;
  EXPECT_EQ(reader.summary().status.rfind("stopped: numerical blow-up at step ", 0), 0u)
      << reader.summary().status;
  EXPECT_NE(reader.summary().status.find("; last good frame " + last), std::string::npos);
  for (std::size_t k = 0; k < frames; ++k) EXPECT_EQ(reader.readFrame(k).size(), 64u);
  const auto info = runShell(sphsplat("info '" + cache + "'"));
  EXPECT_NE(info.output.find("status     stopped: numerical blow-up"), std::string::npos)
      << info.output;
}

TEST_F(CacheCli, InterruptStopsBetweenStepsAndTheRunResumes) {
  const std::string scene = dir_ + "/long.json";
  std::ofstream(scene) << test::tinyCacheScene(3.0, 100);
  const std::string cache = dir_ + "/interrupted.h5";
  const std::string out = dir_ + "/interrupted.log";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
    if (!freopen(out.c_str(), "w", stderr)) _exit(126);
    execl(SPHSPLAT_BINARY, SPHSPLAT_BINARY, "run", scene.c_str(), "--threads", "1", "--quiet", "-o",
          cache.c_str(), "--end", "2.5", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Interrupt once the run is under way (its cache is published after frame 0), not after a fixed
  // delay: on a fast machine the whole second of simulated time takes less than 300 ms.
  for (int waited = 0; waited < 20000 && access(cache.c_str(), F_OK) != 0; ++waited)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 130) << readFile(out);
  const std::string log = readFile(out);
  EXPECT_NE(log.find("sphsplat: interrupted by SIGINT at t = "), std::string::npos) << log;
  // The continue line keeps the run's --end: it finishes the run that was asked for.
  const std::string continueWith =
      "continue with: sphsplat run " + scene + " --end 2.5 --threads 1 --resume " + cache;
  EXPECT_NE(log.find(continueWith), std::string::npos) << log;
  const std::size_t frames = io::cache::CacheReader(cache).frameCount();
  EXPECT_GT(frames, 0u);
  EXPECT_LT(frames, 251u) << "the run should have been stopped before its end";
  EXPECT_NE(io::cache::CacheReader(cache).summary().status.find("interrupted by SIGINT"),
            std::string::npos);
  const auto resumed = runShell(
      sphsplat(continueWith.substr(std::string("continue with: sphsplat ").size()) + " --quiet"));
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_EQ(io::cache::CacheReader(cache).frameCount(), 251u);
}

// A full disk (here a file size limit, which fails writes the same way) stops the run with one line
// saying what the cache keeps; the cache says why it stopped instead of "running", no temporary
// sidecar or partial cache is left, and the run resumes from it.
TEST_F(CacheCli, AFullDiskStopsTheRunWithItsFramesKeptAndSaid) {
  const std::string scene = dir_ + "/long.json";
  std::ofstream(scene) << test::tinyCacheScene(2.0, 100);
  const std::string cache = dir_ + "/full.h5";
  // 1.5 MB (sh counts 512-byte blocks): past frame 0, short of the whole run.
  const auto r =
      runShell("sh -c \"ulimit -f 3000; trap '' XFSZ; exec env " +
               sphsplat("run '" + scene + "' --threads 1 --quiet -o '" + cache + "'") + "\"");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("cannot write frame"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("; the cache " + cache + " keeps frames 0-"), std::string::npos)
      << r.output;
  EXPECT_EQ(lineCount(r.output), 1u) << r.output;
  {  // closed before the resume (HDF5 shares one open file per process)
    const io::cache::CacheReader reader(cache);
    EXPECT_GT(reader.frameCount(), 1u);
    EXPECT_EQ(reader.summary().status.rfind("stopped: writing failed: ", 0), 0u)
        << reader.summary().status;
    for (std::size_t k = 0; k < reader.frameCount(); ++k) EXPECT_GT(reader.readFrame(k).size(), 0u);
  }
  EXPECT_FALSE(test::fileExists(dir_ + "/full.xdmf.tmp"));
  const auto resumed =
      runShell(sphsplat("run '" + scene + "' --threads 1 --quiet --resume '" + cache + "'"));
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_EQ(io::cache::CacheReader(cache).frameCount(), 201u);
  // Full before frame 0 was in: no cache and no partial file at all.
  const std::string none = dir_ + "/none.h5";
  const auto early =
      runShell("sh -c \"ulimit -f 200; trap '' XFSZ; exec env " +
               sphsplat("run '" + scene + "' --threads 1 --quiet -o '" + none + "'") + "\"");
  EXPECT_EQ(early.exitCode, 2) << early.output;
  EXPECT_FALSE(test::fileExists(none));
  EXPECT_FALSE(test::fileExists(none + ".partial"));
}

}  // namespace
}  // namespace sph
