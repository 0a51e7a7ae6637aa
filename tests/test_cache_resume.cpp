// Resume: `sphsplat run SCENE --resume CACHE` continues from the cache's last frame, and a run of
// 2 s equals, bit for bit, a run of 1 s resumed to 2 s with the same thread count: every frame,
// every resume record. Also with a cache that holds positions only (the resume record then carries
// the rest), and with the showcase scene's nozzle. A cache written before the point indexes gets
// them.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <string>

#include "io/cache/CacheReader.h"
#include "tests/CacheFormatSupport.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::runShell;

std::string run(const std::string& scene, const std::string& args) {
  return "OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + scene +
         "' --threads 2 --quiet " + args;
}

void checkResumeEqualsStraightRun(const std::string& dir, const std::string& scene,
                                  const std::string& set, const std::string& half,
                                  const std::string& whole) {
  const std::string straight = dir + "/straight.h5", resumed = dir + "/resumed.h5";
  auto a = runShell(run(scene, set + " --end " + whole + " -o '" + straight + "'"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  auto b = runShell(run(scene, set + " --end " + half + " -o '" + resumed + "'"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  EXPECT_NE(io::cache::CacheReader(resumed).summary().status.find("finished"), std::string::npos);
  auto c = runShell(run(scene, set + " --end " + whole + " --resume '" + resumed + "'"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  test::expectSameCache(straight, resumed);
  EXPECT_GT(io::cache::CacheReader(resumed).summary().frames.back().particles, 0u);
  EXPECT_NE(io::cache::CacheReader(resumed).summary().status.find("finished"), std::string::npos);
  // The sidecar lists every frame, the resumed ones too.
  auto grids = [](const std::string& text) {
    std::size_t n = 0;
    for (std::size_t pos = 0; (pos = text.find("<Grid Name=\"Step#", pos)) != std::string::npos;
         ++pos)
      ++n;
    return n;
  };
  EXPECT_EQ(grids(test::readFile(dir + "/resumed.xdmf")),
            io::cache::CacheReader(resumed).frameCount());
  // Resuming a cache that already reaches the end does nothing.
  auto d = runShell(run(scene, set + " --end " + whole + " --resume '" + resumed + "'"));
  EXPECT_EQ(d.exitCode, 0) << d.output;
  EXPECT_NE(d.output.find("nothing to do"), std::string::npos) << d.output;
}

TEST(CacheResume, TwoSecondsEqualOneSecondResumedToTwo) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(2.0, 30);
  checkResumeEqualsStraightRun(dir, scene, "", "1", "2");
}

// A resume goes on from the cache's frame: it does not settle the fluid again.
TEST(CacheResume, ASettledRunResumesExactly) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.4, 30);
  checkResumeEqualsStraightRun(dir, scene, "--set settle=0.2", "0.2", "0.4");
  const io::cache::CacheReader straight(dir + "/straight.h5");
  EXPECT_EQ(straight.summary().frames.front().time, 0.0);
}

TEST(CacheResume, PositionsOnlyCacheStillResumesExactly) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.6, 30, R"("fields": ["position"])");
  checkResumeEqualsStraightRun(dir, scene, "", "0.3", "0.6");
}

TEST(CacheResume, ARunThatEndedBetweenFrameTimesResumesExactly) {
  // --end 0.11 at 30 frames/s ends with a frame at 0.11 s, off the frame grid, which an
  // uninterrupted run never writes: the resume goes on from the frame at 0.1 s and writes frame
  // 4 again at 0.1333 s. Also an end just before a frame time, and one just after.
  for (const char* half : {"0.11", "0.1333", "0.1334"}) {
    SCOPED_TRACE(std::string("--end ") + half);
    const std::string dir = test::makeTempDir();
    const std::string scene = dir + "/tiny.json";
    std::ofstream(scene) << test::tinyCacheScene(0.3, 30);
    checkResumeEqualsStraightRun(dir, scene, "", half, "0.3");
  }
}

TEST(CacheResume, ARenderingRunThatEndedBetweenFrameTimesGetsThatFramesImageAgain) {
  // The images stored in the cache (/Render#<renderer>#N) of the frame written again are the new
  // frame's: the same as an uninterrupted run's.
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/render.json";
  std::ofstream(scene) << test::tinyRenderingScene(0.2, 20);
  checkResumeEqualsStraightRun(dir, scene, "", "0.12", "0.2");
  const io::cache::CacheReader straight(dir + "/straight.h5"), resumed(dir + "/resumed.h5");
  ASSERT_EQ(resumed.frameCount(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    const auto a = straight.readRenderedFrame("quad", k), b = resumed.readRenderedFrame("quad", k);
    EXPECT_EQ(a.rgb, b.rgb) << "frame " << k;
  }
}

TEST(CacheResume, ShowcasePourSceneResumesExactly) {
  // The shipped pour scene, coarser so the test stays quick; the nozzle is running at the cut.
  // WCSPH's wall shares travel in the resume record (wcsph_wall_share): without them the resumed
  // half would differ from the straight run.
  const std::string dir = test::makeTempDir();
  checkResumeEqualsStraightRun(dir, test::sourcePath("scenes/pour.json"),
                               "--set solver.spacing=0.01 --set render.width=320 "
                               "--set render.height=180",
                               "0.2", "0.4");
  const auto [state, fluid] = io::cache::CacheReader(dir + "/resumed.h5").readRestart(5);
  ASSERT_EQ(state.warmStart.wallShare.size(), fluid.size());
  EXPECT_TRUE(std::any_of(state.warmStart.wallShare.begin(), state.warmStart.wallShare.end(),
                          [](float s) { return s != 0; }));
}

TEST(CacheResume, DfsphPourSceneResumesExactly) {
  // DFSPH's warm start travels in the resume record (dfsph_warm_density, dfsph_warm_divergence):
  // without it the resumed half would differ from the straight run.
  const std::string dir = test::makeTempDir();
  checkResumeEqualsStraightRun(dir, test::sourcePath("scenes/pour.json"),
                               "--set solver.spacing=0.01 --set solver.pressure=dfsph", "0.2",
                               "0.4");
  const auto [state, fluid] = io::cache::CacheReader(dir + "/resumed.h5").readRestart(5);
  ASSERT_EQ(state.warmStart.density.size(), fluid.size());
  ASSERT_EQ(state.warmStart.divergence.size(), fluid.size());
}

TEST(CacheResume, ACacheWrittenBeforeThePointIndexesGetsThoseItsSidecarNames) {
  // Caches written before the sidecar gave its points cells have no /Index#L; the sidecar a
  // resume rewrites names them for every frame, the old ones too. The tank is widened to 1232
  // boundary particles: their index (Index#2048) is then not one the frames written after the
  // resume (about 100 particles, Index#1024) write anyway.
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::string text = test::tinyCacheScene(0.2, 30);
  text.replace(text.find("[0.2, 0.2, 0.15]"), 16, "[0.4, 0.2, 0.15]");
  std::ofstream(scene) << text;
  const std::string cache = dir + "/old.h5";
  ASSERT_EQ(runShell(run(scene, "--end 0.1 -o '" + cache + "'")).exitCode, 0);
  {
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_file_locking(fapl, false, true);
    test::Id file(H5Fopen(cache.c_str(), H5F_ACC_RDWR, fapl));
    H5Pclose(fapl);
    int removed = 0;
    for (const std::string& name : test::rootLinks(file)) {
      if (name.rfind("Index#", 0) == 0) removed += H5Ldelete(file, name.c_str(), H5P_DEFAULT) >= 0;
    }
    ASSERT_GT(removed, 0);
  }
  const auto r = runShell(run(scene, "--resume '" + cache + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string xdmf = test::readFile(dir + "/old.xdmf");
  test::Id file(test::openRaw(cache));
  const std::regex item("old\\.h5:(/[^<]+)</DataItem>");
  int indexes = 0;
  for (auto m = std::sregex_iterator(xdmf.begin(), xdmf.end(), item); m != std::sregex_iterator();
       ++m) {
    const std::string dataset = (*m)[1];
    EXPECT_GT(H5Oexists_by_name(file, dataset.c_str(), H5P_DEFAULT), 0) << dataset;
    indexes += dataset.rfind("/Index#", 0) == 0;
  }
  // The fluid's and the boundary's cells in each of the 7 frames.
  EXPECT_EQ(indexes, 2 * 7);
  EXPECT_NE(xdmf.find("old.h5:/Index#2048</DataItem>"), std::string::npos);
}

TEST(CacheResume, RefusesAnotherScene) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.1, 100);
  const std::string cache = dir + "/c.h5";
  ASSERT_EQ(runShell(run(scene, "-o '" + cache + "'")).exitCode, 0);
  const auto r =
      runShell(run(scene, "--set solver.spacing=0.03 --end 0.2 --resume '" + cache + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("not the scene the cache " + cache +
                          " was written with (solver.spacing is 0.03 here but "
                          "0.025 in the cache)"),
            std::string::npos)
      << r.output;
  const auto moved = runShell(
      run(scene, "--set fluids[0].max=[0.1,0.125,0.15] --end 0.2 --resume '" + cache + "'"));
  EXPECT_EQ(moved.exitCode, 2) << moved.output;
  EXPECT_NE(moved.output.find("fluids, boundaries, emitters or domain differ"), std::string::npos)
      << moved.output;
  // A block taller than the nozzle: the automatic speed of sound follows its height, but the
  // block is what changed (this said "solver.speed_of_sound is ... here but ... in the cache").
  const auto taller = runShell(
      run(scene, "--set fluids[0].max=[0.1,0.19,0.15] --end 0.2 --resume '" + cache + "'"));
  EXPECT_EQ(taller.exitCode, 2) << taller.output;
  EXPECT_NE(taller.output.find("(its fluids, boundaries, emitters or domain differ; derived from "
                               "them, solver.speed_of_sound is "),
            std::string::npos)
      << taller.output;
  EXPECT_EQ(io::cache::CacheReader(cache).frameCount(), 11u)
      << "a refused resume leaves the cache alone";
}

// The sidecar cannot be written (here its temporary name is taken by a directory; on a user's
// machine, a disk that filled): the resume fails with one line, and the cache it resumed keeps
// every frame it had. So does a cache that an --overwrite run replaced at its frame 0.
TEST(CacheResume, ASidecarThatCannotBeWrittenLeavesTheCache) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.2, 30);
  const std::string cache = dir + "/r.h5";
  ASSERT_EQ(runShell(run(scene, "--end 0.1 -o '" + cache + "'")).exitCode, 0);
  const std::size_t frames = io::cache::CacheReader(cache).frameCount();
  ASSERT_EQ(frames, 4u);
  ASSERT_EQ(::mkdir((dir + "/r.xdmf.tmp").c_str(), 0755), 0);
  const auto resumed = runShell(run(scene, "--resume '" + cache + "'"));
  EXPECT_EQ(resumed.exitCode, 2) << resumed.output;
  EXPECT_NE(resumed.output.find("r.xdmf"), std::string::npos) << resumed.output;
  ASSERT_TRUE(test::fileExists(cache)) << "the resume deleted the cache: " << resumed.output;
  EXPECT_GE(io::cache::CacheReader(cache).frameCount(), frames);

  const auto replaced = runShell(run(scene, "--end 0.1 --overwrite -o '" + cache + "'"));
  EXPECT_EQ(replaced.exitCode, 2) << replaced.output;
  ASSERT_TRUE(test::fileExists(cache)) << "no cache left: " << replaced.output;
  EXPECT_GE(io::cache::CacheReader(cache).frameCount(), 1u);
  EXPECT_FALSE(test::fileExists(cache + ".partial"));
}

// A scene named like the cache's sidecar: the resume would write the sidecar over it, which a new
// run refuses too.
TEST(CacheResume, RefusesToWriteTheSidecarOverTheScene) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/y.json", cache = dir + "/y.h5", named = dir + "/y.xdmf";
  std::ofstream(scene) << test::tinyCacheScene(0.2, 30);
  ASSERT_EQ(runShell(run(scene, "--end 0.1 -o '" + cache + "'")).exitCode, 0);
  std::ofstream(named, std::ios::trunc) << test::tinyCacheScene(0.2, 30);
  const auto r = runShell(run(named, "--resume '" + cache + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("is the scene file being run"), std::string::npos) << r.output;
  EXPECT_EQ(test::readFile(named), test::tinyCacheScene(0.2, 30)) << "the scene was overwritten";
}

}  // namespace
}  // namespace sph
