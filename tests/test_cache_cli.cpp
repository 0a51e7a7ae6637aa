// The cache commands as a user meets them: `run --output` with its summary, `info`, `export`,
// refusing to overwrite, every kind of bad cache refused with one line and exit code 2, a blow-up
// keeping its finished frames and naming the last good one, Ctrl-C stopping with a resumable cache.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "io/cache/CacheReader.h"
#include "io/UserFiles.h"
#include "io/cache/XdmfWriter.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::readFile;
using test::runShell;

using test::lineCount;
std::string sphsplat(const std::string& args) {
  return test::sphsplatShell(args);
}

class CacheCli : public test::TinyCacheSuite {};

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

TEST_F(CacheCli, InfoDescribesTheCache) {
  const auto r = runShell(sphsplat("info '" + cache_ + "' --frames"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const std::string& expected : std::vector<std::string>{
           cache_ + ": sphsplat cache (format 1", "scene      tiny (" + scene_ + ")",
           "status     finished at t = 0.1 s",
           "frames     11 (Step#0 - Step#10), t = 0 - 0.1 s at 100 frames/s",
           "particles  96 - 98 fluid per frame (98 in the last), ",
           "fields     x y z vx vy vz rho p id (float32, id uint32), deflate 4 + shuffle",
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

// A symbolic link that leads nowhere is said to be one, not "already exists" (a run's cache and
// an export's file alike), and --overwrite replaces the link.
TEST_F(CacheCli, ALinkThatLeadsNowhereIsSaidToBeOne) {
  const std::string dangling = dir_ + "/dangling.h5", loop = dir_ + "/loop.h5";
  std::filesystem::create_symlink("nowhere/x.h5", dangling);
  std::filesystem::create_symlink("loop.h5", loop);
  auto r = runShell(sphsplat("run '" + scene_ + "' --quiet -o '" + dangling + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(dangling + ": is a symbolic link to nowhere/x.h5, which does not exist; "
                                     "pass --overwrite to replace it"),
            std::string::npos)
      << r.output;
  r = runShell(sphsplat("run '" + scene_ + "' --quiet -o '" + loop + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(loop + ": is a symbolic link that loops; pass --overwrite"),
            std::string::npos)
      << r.output;
  r = runShell(sphsplat("export '" + cache_ + "' --frames 1 -o '" + loop + ".csv'"));
  EXPECT_EQ(r.exitCode, 0) << "a new name: " << r.output;
  std::filesystem::create_symlink("loop.csv", dir_ + "/loop.csv");
  r = runShell(sphsplat("export '" + cache_ + "' --frames 1 -o '" + dir_ + "/loop.csv'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("/loop.csv: is a symbolic link that loops; pass --overwrite"),
            std::string::npos)
      << r.output;
  r = runShell(sphsplat("run '" + scene_ + "' --quiet --overwrite -o '" + dangling + "'"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_FALSE(std::filesystem::is_symlink(dangling)) << "the link is replaced by the cache";
}

TEST_F(CacheCli, RefusesToOverwriteUnlessAsked) {
  const std::string before = readFile(cache_);
  auto r = runShell(sphsplat("run '" + scene_ + "' --threads 1 -o '" + cache_ + "'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output, "sphsplat: " + cache_ +
                          ": already exists; pass --overwrite to replace it, or --resume " +
                          cache_ + " to continue that run\n");
  EXPECT_EQ(readFile(cache_), before) << "the existing cache was touched";
  // Pointing the cache at the scene file itself.
  const std::string sceneText = readFile(scene_);
  r = runShell(sphsplat("run '" + scene_ + "' -o '" + scene_ + "'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(readFile(scene_), sceneText);
  // --overwrite replaces it (a new creation time, same frames).
  const std::string copy = dir_ + "/copy.h5";
  std::ofstream(copy) << "old contents";
  r = runShell(sphsplat("run '" + scene_ + "' --threads 1 --quiet --overwrite -o '" + copy + "'"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(io::CacheReader(copy).frameCount(), 11u);
  r = runShell(sphsplat("run '" + scene_ + "' -o '" + dir_ + "/no/such/dir/c.h5'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output, "sphsplat: " + dir_ + "/no/such/dir/c.h5: cannot create the cache in " +
                          dir_ + "/no/such/dir (No such file or directory)\n");
}

struct BadCache {
  std::string what, command, message;  // message: the whole expected line after "sphsplat: "
};

TEST_F(CacheCli, EveryBadCacheGivesOneLineAndExitTwo) {
  const std::string text = dir_ + "/notes.txt";
  std::ofstream(text) << "not a cache\n";
  // A cache cut in half (an interrupted copy).
  const std::string truncated = dir_ + "/truncated.h5";
  const std::string whole = readFile(cache_);
  std::ofstream(truncated, std::ios::binary) << whole.substr(0, whole.size() / 2);
  // An HDF5 file from another program.
  const std::string foreign = dir_ + "/foreign.h5";
  {
    const hid_t f = H5Fcreate(foreign.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = 4;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t d = H5Dcreate2(f, "temperature", H5T_NATIVE_FLOAT, space, H5P_DEFAULT, H5P_DEFAULT,
                               H5P_DEFAULT);
    H5Dclose(d), H5Sclose(space), H5Fclose(f);
  }
  // A cache with positions only, asked for densities.
  const std::string positions = dir_ + "/positions.h5";
  const std::string posScene = dir_ + "/positions.json";
  std::ofstream(posScene) << test::tinyCacheScene(0.02, 100,
                                                  R"("fields": ["position"], "restart": false)");
  ASSERT_EQ(runShell(sphsplat("run '" + posScene + "' --threads 1 --quiet -o '" + positions + "'"))
                .exitCode,
            0);

  const std::vector<BadCache> cases = {
      {"missing", "info '" + dir_ + "/nope.h5'",
       dir_ + "/nope.h5: cannot open the cache (No such file or directory)"},
      {"directory", "info '" + dir_ + "'", dir_ + ": is a directory, expected an HDF5 cache file"},
      {"not HDF5", "info '" + text + "'",
       text + ": not an HDF5 file (no HDF5 signature); expected a sphsplat cache"},
      {"truncated", "info '" + truncated + "'",
       truncated + ": truncated HDF5 file: " + std::to_string(whole.size() / 2) +
           " bytes, but its superblock says " + std::to_string(whole.size()) +
           " (an interrupted copy or download?)"},
      {"foreign HDF5", "export '" + foreign + "' --frame 0 --format csv -o -",
       foreign + ": an HDF5 file but not a sphsplat cache (no root attribute 'sphsplat_format'; "
                 "written by another program?)"},
      {"missing dataset", "export '" + positions + "' --frame 1 --format csv --fields rho -o -",
       positions + ": frame 1 has no dataset /Step#1/rho (it holds x y z)"},
      {"frame out of range", "export '" + cache_ + "' --frame 11 --format ply -o -",
       "--frames: frames 11 are not in the cache (it has frames 0 to 10)"},
      {"bad frame text", "export '" + cache_ + "' --frame two --format csv -o -",
       "--frames: expected a frame index (0, 1, ...), 'last' or -1, got 'two'"},
      {"resume a foreign file", "run '" + scene_ + "' --resume '" + foreign + "'",
       foreign + ": an HDF5 file but not a sphsplat cache (no root attribute 'sphsplat_format'; "
                 "written by another program?)"},
      {"resume a truncated file", "run '" + scene_ + "' --resume '" + truncated + "'",
       truncated + ": truncated HDF5 file: " + std::to_string(whole.size() / 2) +
           " bytes, but its superblock says " + std::to_string(whole.size()) +
           " (an interrupted copy or download?)"},
      {"resume without records", "run '" + posScene + "' --end 0.05 --resume '" + positions + "'",
       positions + ": frame 2 has no resume record (/Restart#2): the run was written with "
                   "output.restart = false"},
  };
  for (const BadCache& c : cases) {
    const auto r = runShell(sphsplat(c.command));
    EXPECT_EQ(r.exitCode, 2) << c.what << "\n" << r.output;
    EXPECT_EQ(r.output, "sphsplat: " + c.message + "\n") << c.what;
  }
  EXPECT_EQ(readFile(truncated).size(), whole.size() / 2)
      << "a failed resume must not touch the file";
}

// A legal name near the file system's 255-byte limit gets its lock (.NAME.lock), its temporary
// (NAME.partial) and its sidecar, whose names are shortened with a hash where they would pass it.
TEST_F(CacheCli, NamesNearTheLimitGetTheirLockTemporaryAndSidecar) {
  for (const std::size_t bytes : {246u, 250u, 255u}) {
    const std::string name = std::string(bytes - 3, 'n') + ".h5";
    const std::string cache = dir_ + "/" + name;
    const auto r = runShell(sphsplat("run '" + scene_ + "' --threads 1 --quiet --end 0.02 -o '" +
                                     cache + "'"));
    EXPECT_EQ(r.exitCode, 0) << bytes << " bytes: " << r.output;
    EXPECT_EQ(io::CacheReader(cache).frameCount(), 3u) << bytes;
    const std::string sidecar = io::XdmfWriter::sidecarPath(cache);
    EXPECT_TRUE(test::fileExists(sidecar)) << sidecar;
    EXPECT_LE(sidecar.size() - dir_.size() - 1, 255u);
    EXPECT_NE(readFile(sidecar).find(name), std::string::npos) << "the sidecar names the cache";
    // The export of its frames beside it (NAME.partial-XXXXXX while written).
    const auto e = runShell(sphsplat("export '" + cache + "' --frame 0 --format csv -o '" +
                                     dir_ + "/" + std::string(bytes - 4, 'e') + ".csv'"));
    EXPECT_EQ(e.exitCode, 0) << bytes << " bytes: " << e.output;
  }
  EXPECT_EQ(io::siblingPath("/d/abc", ".", ".lock"), "/d/.abc.lock");
  const std::string shortened = io::siblingPath("/d/" + std::string(255, 'a'), "", ".partial");
  EXPECT_EQ(shortened.size(), 3u + 255u);
  EXPECT_EQ(shortened.substr(shortened.size() - 8), ".partial");
  EXPECT_NE(shortened, io::siblingPath("/d/" + std::string(254, 'a') + "b", "", ".partial"));
}

// The header's texts (the format name, the scene) are variable-length strings, which HDF5 keeps
// in a global heap without a checksum and copies by the sizes it finds there: a damaged size or
// index is said in one line with exit 2 by every command that reads the header, never a crash.
TEST_F(CacheCli, ADamagedHeapObjectOfTheHeaderIsSaidNotCrashedOn) {
  const std::string whole = readFile(cache_);
  const std::string name("sphsplat-cache\0", 15);
  const std::size_t at = whole.find(name);
  ASSERT_NE(at, std::string::npos);
  ASSERT_GE(at, 16u);
  const std::string damaged = dir_ + "/heap.h5";
  int refused = 0;
  // The heap object's header before the text: index (2 bytes), references (2), reserved (4),
  // size (8).
  for (std::size_t offset = at - 16; offset < at; ++offset) {
    for (const unsigned char value : {0x00, 0x32, 0xff}) {
      if (static_cast<unsigned char>(whole[offset]) == value) continue;
      std::string bytes = whole;
      bytes[offset] = static_cast<char>(value);
      std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
      const std::string label = "byte " + std::to_string(offset - at + 16) + " of the object's "
                                "header set to " + std::to_string(value);
      for (const std::string& command :
           {"info '" + damaged + "'", "export '" + damaged + "' --frame 0 --format csv -o -",
            "mesh '" + damaged + "' --frame 0 -o '" + dir_ + "/heap_mesh'",
            "run '" + scene_ + "' --resume '" + damaged + "'"}) {
        const auto r = runShell(sphsplat(command));
        EXPECT_TRUE(r.exitCode == 0 || r.exitCode == 2) << label << ": " << command << "\n"
                                                        << r.output;
        if (r.exitCode == 2) {
          EXPECT_EQ(lineCount(r.output), 1u) << label << ": " << command << "\n" << r.output;
          ++refused;
        }
        std::filesystem::remove_all(dir_ + "/heap_mesh");
      }
      // The size and the index (not the reference count or the reserved bytes) make the text
      // unreadable.
      const std::size_t field = offset - (at - 16);
      if (field < 2 || field >= 8) {
        const auto r = runShell(sphsplat("info '" + damaged + "'"));
        EXPECT_NE(r.output.find("global heap"), std::string::npos) << label << "\n" << r.output;
      }
      if (HasFailure()) return;
    }
  }
  EXPECT_GT(refused, 0);
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

// A FIFO named as a cache: opening it would wait for a writer for ever. Every command that reads a
// cache refuses it at once (each under `timeout`, so that a regression fails rather than hangs).
TEST_F(CacheCli, AFifoGivenAsACacheIsRefusedNotWaitedOn) {
  const std::string fifo = dir_ + "/f.h5";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  for (const std::string& args :
       {"info '" + fifo + "'", "export '" + fifo + "' --frame 0 --format csv -o -",
        "mesh '" + fifo + "' --frame 0 --out '" + dir_ + "/f.ply'",
        "render '" + fifo + "' --out '" + dir_ + "/f_frames'",
        "run '" + scene_ + "' --resume '" + fifo + "'"}) {
    const auto r =
        runShell("timeout 60 env OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " " + args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
    EXPECT_EQ(r.output,
              "sphsplat: " + fifo + ": is a FIFO (named pipe), expected an HDF5 cache file\n")
        << args;
  }
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
  const io::CacheReader reader(cache);
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
  const std::size_t frames = io::CacheReader(cache).frameCount();
  EXPECT_GT(frames, 0u);
  EXPECT_LT(frames, 251u) << "the run should have been stopped before its end";
  EXPECT_NE(io::CacheReader(cache).summary().status.find("interrupted by SIGINT"),
            std::string::npos);
  const auto resumed = runShell(
      sphsplat(continueWith.substr(std::string("continue with: sphsplat ").size()) + " --quiet"));
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_EQ(io::CacheReader(cache).frameCount(), 251u);
}

TEST_F(CacheCli, NonRegularFilesAreNeverReplaced) {
  // FIFOs everywhere; character devices (mknod copies of /dev/null and /dev/full) where the
  // test may create them. `run --overwrite` used to replace them with a plain file.
  ASSERT_EQ(mkfifo((dir_ + "/fifo.h5").c_str(), 0644), 0);
  ASSERT_EQ(mkfifo((dir_ + "/side.xdmf").c_str(), 0644), 0);  // the sidecar of side.h5
  const bool root = geteuid() == 0;
  if (root) {
    ASSERT_EQ(mknod((dir_ + "/null.h5").c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);
    ASSERT_EQ(mknod((dir_ + "/full.csv").c_str(), S_IFCHR | 0666, makedev(1, 7)), 0);
  }
  // A timeout: opening a FIFO blocks, which is how the old code hung here.
  auto run = [&](const std::string& args) {
    return runShell("OMP_WAIT_POLICY=PASSIVE timeout 60 " + test::sphsplatBinary() + " " + args);
  };
  std::vector<std::pair<std::string, test::CommandResult>> results = {
      {dir_ + "/fifo.h5",
       run("run '" + scene_ + "' --quiet --overwrite -o '" + dir_ + "/fifo.h5'")},
      {dir_ + "/side.xdmf",
       run("run '" + scene_ + "' --quiet --overwrite -o '" + dir_ + "/side.h5'")},
      {dir_ + "/fifo.h5",
       run("export '" + cache_ + "' --format csv --overwrite -o '" + dir_ + "/fifo.h5'")},
  };
  if (root) {
    results.push_back({dir_ + "/null.h5",
                       run("run '" + scene_ + "' --quiet --overwrite -o '" + dir_ + "/null.h5'")});
    results.push_back({dir_ + "/full.csv",
                       run("export '" + cache_ + "' --overwrite -o '" + dir_ + "/full.csv'")});
  }
  for (const auto& [path, r] : results) {
    EXPECT_EQ(r.exitCode, 2) << path << "\n" << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find(path + ": is a "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(", not a regular file; refusing to replace it"), std::string::npos)
        << r.output;
    struct stat st {};
    ASSERT_EQ(lstat(path.c_str(), &st), 0) << path;
    EXPECT_FALSE(S_ISREG(st.st_mode)) << path << " was replaced by a plain file";
  }
  EXPECT_FALSE(test::fileExists(dir_ + "/side.h5")) << "nothing is written when a check fails";
}

// info, export, mesh: what the complete frames allow, then the damage in one line and exit 2
// ("all" and "last" quietly meaning the frames before the damaged one was the old behaviour).
TEST_F(CacheCli, ADamagedCacheIsSaidAndExitsTwoAfterWhatCouldBeRead) {
  const std::string damaged = dir_ + "/damaged.h5";
  std::filesystem::copy_file(cache_, damaged);
  {
    const hid_t f = H5Fopen(damaged.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t g = H5Gopen2(f, "Step#3", H5P_DEFAULT);
    ASSERT_GE(H5Adelete(g, "TimeValue"), 0);
    H5Gclose(g), H5Fclose(f);
  }
  const auto r = runShell(sphsplat("info '" + damaged + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;  // was 0
  EXPECT_NE(r.output.find("frames     3 (Step#0 - Step#2)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sphsplat: " + damaged +
                          ": damaged cache: frame 3 does not read back (/Step#3: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("; frames 0-2 are complete\n"), std::string::npos) << r.output;
  const std::string damageLine = damaged + ": damaged cache: frame 3 does not read back";
  struct Case {
    std::string command, firstFile, lastFile;
  };
  const Case cases[] = {
      {"export '" + damaged + "' --frames all --format csv -o '" + dir_ + "/all/'",
       dir_ + "/all/tiny_00000.csv", dir_ + "/all/tiny_00002.csv"},
      {"export '" + damaged + "' --frames last -o '" + dir_ + "/last.csv'", dir_ + "/last.csv",
       dir_ + "/last.csv"},
      {"mesh '" + damaged + "' --frames all -q -o '" + dir_ + "/mesh/'",
       dir_ + "/mesh/tiny_00000.ply", dir_ + "/mesh/tiny_00002.ply"},
  };
  for (const Case& c : cases) {
    const auto e = runShell(sphsplat(c.command));
    EXPECT_EQ(e.exitCode, 2) << c.command << "\n" << e.output;  // was 0, silently
    EXPECT_NE(e.output.find(damageLine), std::string::npos) << c.command << "\n" << e.output;
    EXPECT_TRUE(test::fileExists(c.firstFile)) << c.command;
    EXPECT_TRUE(test::fileExists(c.lastFile)) << c.command;
  }
  EXPECT_FALSE(test::fileExists(dir_ + "/all/tiny_00003.csv"));
}

// Issue 12, item 10: a full disk (here a file size limit, which fails writes the same way) stops
// the run with one line saying what the cache keeps; the cache says why it stopped instead of
// "running", no temporary sidecar or partial cache is left, and the run resumes from it.
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
    const io::CacheReader reader(cache);
    EXPECT_GT(reader.frameCount(), 1u);
    EXPECT_EQ(reader.summary().status.rfind("stopped: writing failed: ", 0), 0u)
        << reader.summary().status;
    for (std::size_t k = 0; k < reader.frameCount(); ++k) EXPECT_GT(reader.readFrame(k).size(), 0u);
  }
  EXPECT_FALSE(test::fileExists(dir_ + "/full.xdmf.tmp"));
  const auto resumed =
      runShell(sphsplat("run '" + scene + "' --threads 1 --quiet --resume '" + cache + "'"));
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_EQ(io::CacheReader(cache).frameCount(), 201u);
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
