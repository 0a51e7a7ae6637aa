// Where the cache commands may write and what they may open: an existing cache or the scene itself
// is never overwritten unless asked, a link that leads nowhere is said to be one, names near the
// file system's limit get their lock, temporary and sidecar, and FIFOs and device nodes are
// refused, never waited on or replaced by a plain file.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/UserFiles.h"
#include "io/cache/XdmfWriter.h"
#include "tests/CacheCliSuite.h"

namespace sph {
namespace {

using test::CacheCli;
using test::lineCount;
using test::readFile;
using test::runShell;
using test::sphsplat;

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
  EXPECT_EQ(io::cache::CacheReader(copy).frameCount(), 11u);
  r = runShell(sphsplat("run '" + scene_ + "' -o '" + dir_ + "/no/such/dir/c.h5'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output, "sphsplat: " + dir_ + "/no/such/dir/c.h5: cannot create the cache in " +
                          dir_ + "/no/such/dir (No such file or directory)\n");
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
    EXPECT_EQ(io::cache::CacheReader(cache).frameCount(), 3u) << bytes;
    const std::string sidecar = io::cache::XdmfWriter::sidecarPath(cache);
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

}  // namespace
}  // namespace sph
