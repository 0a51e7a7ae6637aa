// The rain's drops in the cache (docs/cache-format.md, "Rain drops"): a run of a scene with rain
// stores every frame's drops as /Rain#N - exactly the drops the scene's rain stepper gives at that
// frame - the XDMF sidecar lists them as a third point set, `info` counts them, and a cache without
// rain holds none of it.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>

#include "io/cache/CacheReader.h"
#include "io/cache/Hdf5.h"
#include "io/cache/RainCache.h"
#include "io/scene/SceneLoader.h"
#include "sim/InputError.h"
#include "sim/rain/RainStepper.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::runShell;

constexpr std::size_t kDrops = 500;

// tinyCacheScene with a camera and rain (no render section: the run draws nothing).
// `feedKeys`: more keys of the rain section (rain.feed_fluid).
std::string rainScene(double endTime, const std::string& feedKeys = "") {
  std::string scene = test::tinyCacheScene(endTime, 20);
  const std::string rain =
      R"(  "camera": {"position": [0.5, 0.4, 0.5], "target": [0.1, 0.05, 0.075], "fov": 40,
             "path": [{"time": 0}, {"time": 1, "position": [-0.3, 0.4, 0.5]}]},
  "rain": {"count": )" +
      std::to_string(kDrops) + R"(, "near": 0.05, "far": 0.8, "fall_speed": 3, "seed": 7)" +
      feedKeys + R"(},
)";
  return scene.insert(scene.find("  \"output\""), rain);
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t pos = 0; (pos = text.find(what, pos)) != std::string::npos; ++pos) ++n;
  return n;
}

bool sameBits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

TEST(RainCache, RunStoresEveryFramesDropsAndTheSidecarAndInfoShowThem) {
  const std::string dir = test::makeTempDir();
  const std::string scenePath = dir + "/rain.json", cache = dir + "/rain.h5";
  std::ofstream(scenePath) << rainScene(0.2);
  auto r = runShell(test::sphsplatShell("run " + scenePath + " --threads 2 -q -o " + cache));
  ASSERT_EQ(r.exitCode, 0) << r.output;

  const io::cache::CacheReader reader(cache);
  ASSERT_EQ(reader.frameCount(), 5u);  // 0.2 s at 20 fps
  // The drops of each frame are the stepper's at that frame's time with that frame's water.
  const scene::Scene scene = io::scene::loadScene(scenePath);
  auto stepper = rain::RainStepper::create(scene, rain::RainStepper::sceneAspect(scene));
  std::vector<Vec3> previous;
  for (std::size_t k = 0; k < reader.frameCount(); ++k) {
    ASSERT_EQ(reader.summary().frames[k].rainDrops, kDrops) << k;
    const io::cache::RainFrame stored = io::cache::readRainFrame(reader, k);
    EXPECT_EQ(stored.time, reader.summary().frames[k].time);
    stepper->advanceTo(stored.time, reader.readFrame(k));
    EXPECT_TRUE(sameBits(stored.positions, stepper->system().positions())) << "frame " << k;
    EXPECT_EQ(stored.generations, stepper->system().generations()) << k;
    EXPECT_EQ(stored.layers, stepper->system().layers()) << k;
    for (const Vec3& p : stored.positions)
      ASSERT_TRUE(stepper->system().space().contains(p)) << "frame " << k;
    EXPECT_FALSE(sameBits(stored.positions, previous)) << "the drops fall: frame " << k;
    previous = stored.positions;
  }
  // The sidecar: a `rain` grid per frame, [drops][3] from the frame's Rain#N.
  const std::string xdmf = test::readFile(dir + "/rain.xdmf");
  EXPECT_EQ(count(xdmf, "<Grid Name=\"rain\""), reader.frameCount());
  EXPECT_EQ(count(xdmf, "\"" + std::to_string(kDrops) +
                            " 3\" NumberType=\"Float\" Precision=\"4\" "
                            "Format=\"HDF\">rain.h5:/Rain#"),
            reader.frameCount());
  EXPECT_NE(xdmf.find("rain.h5:/Rain#4/position</DataItem>"), std::string::npos);
  // h5py (what ParaView's readers see): Rain#N/position is [drops][3] float32.
  r = runShell("/usr/bin/python3 -c \"import h5py; f = h5py.File('" + cache +
               "', 'r'); d = f['Rain#3/position']; print(d.shape, d.dtype, "
               "f['Rain#3'].attrs['drops'])\"");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("(500, 3) float32 500"), std::string::npos) << r.output;
  r = runShell(test::sphsplatShell("info " + cache));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("rain       500 drops per frame in 5 frames"), std::string::npos)
      << r.output;
}

TEST(RainCache, ACacheWithoutRainHoldsNoneOfIt) {
  const std::string dir = test::makeTempDir();
  const std::string scenePath = dir + "/tiny.json", cache = dir + "/tiny.h5";
  std::ofstream(scenePath) << test::tinyCacheScene(0.1, 30);
  auto r = runShell(test::sphsplatShell("run " + scenePath + " --threads 2 -q -o " + cache));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const io::cache::CacheReader reader(cache);
  for (const io::cache::CacheFrame& f : reader.summary().frames) EXPECT_EQ(f.rainDrops, 0u);
  EXPECT_FALSE(io::cache::h5::hasLink(reader.file(), "Rain#0"));
  EXPECT_EQ(test::readFile(dir + "/tiny.xdmf").find("rain"), std::string::npos);
  r = runShell(test::sphsplatShell("info " + cache));
  EXPECT_EQ(r.output.find("rain"), std::string::npos) << r.output;
  EXPECT_THROW(io::cache::readRainFrame(reader, 0), InputError);
}

// Runs `scene` (written as dir/scene.json) to 0.2 s straight (dir/straight.h5) and to 0.1 s then
// resumed to 0.2 s (dir/resumed.h5), and expects the two caches and their drops bit-identical.
void expectResumedEqualsStraight(const std::string& dir, const std::string& scene,
                                 const std::string& half = "0.1") {
  const std::string scenePath = dir + "/scene.json";
  std::ofstream(scenePath) << scene;
  const std::string straight = dir + "/straight.h5", resumed = dir + "/resumed.h5";
  auto run = [&](const std::string& args) {
    return runShell(test::sphsplatShell("run " + scenePath + " --threads 2 -q " + args));
  };
  auto a = run("--end 0.2 -o " + straight);
  ASSERT_EQ(a.exitCode, 0) << a.output;
  auto b = run("--end " + half + " -o " + resumed);
  ASSERT_EQ(b.exitCode, 0) << b.output;
  auto c = run("--end 0.2 --resume " + resumed);
  ASSERT_EQ(c.exitCode, 0) << c.output;
  test::expectSameCache(straight, resumed);  // fluid, resume records (the rain feed's ledger)
  const io::cache::CacheReader ra(straight), rb(resumed);
  ASSERT_EQ(ra.frameCount(), 5u);
  ASSERT_EQ(rb.frameCount(), 5u);
  for (std::size_t k = 0; k < ra.frameCount(); ++k) {
    const io::cache::RainFrame x = io::cache::readRainFrame(ra, k),
                               y = io::cache::readRainFrame(rb, k);
    EXPECT_TRUE(sameBits(x.positions, y.positions)) << "frame " << k;
    EXPECT_EQ(x.generations, y.generations) << "frame " << k;
  }
  EXPECT_EQ(count(test::readFile(dir + "/resumed.xdmf"), "<Grid Name=\"rain\""), rb.frameCount());
}

TEST(RainCache, AResumedRunContinuesTheDropsBitForBit) {
  expectResumedEqualsStraight(test::makeTempDir(), rainScene(0.2));
}

// rain.feed_fluid: the landed rain's particles, the pending water and the drops are all part of
// the run's state, so a resume continues the fluid exactly (tests/test_rain_feed.cpp has the
// physics).
TEST(RainCache, AResumedRunThatEndedBetweenFrameTimesGetsThatFramesDropsAgain) {
  // The run ends at 0.13 s, between the frames at 0.1 and 0.15 s: the resume steps the drops on
  // from 0.1 s and stores frame 3's again at 0.15 s.
  expectResumedEqualsStraight(test::makeTempDir(), rainScene(0.2), "0.13");
}

// The landed rain's particles join the fluid at a tick, after the step: the solver's per-particle
// state (DFSPH's warm start here, WCSPH's wall shares above) must cover them in the frame written
// then, or the resumed run starts them from another state than the straight one did.
TEST(RainCache, AResumedFeedingDfsphRunContinuesBitForBit) {
  const std::string dir = test::makeTempDir();
  std::string scene = rainScene(0.2, R"(, "feed_fluid": true, "drop_volume": 3.90625e-6)");
  const std::string solver = "\"solver\": {";
  scene.insert(scene.find(solver) + solver.size(), R"("pressure": "dfsph", )");
  expectResumedEqualsStraight(dir, scene);
  if (HasFatalFailure()) return;
  const auto [state, fluid] = io::cache::CacheReader(dir + "/resumed.h5").readRestart(4);
  EXPECT_GT(state.rain.particles, 0u);  // rain joined the fluid
  EXPECT_EQ(state.warmStart.density.size(), fluid.size());
}

TEST(RainCache, AResumedFeedingRunContinuesTheFluidAndTheDropsBitForBit) {
  const std::string dir = test::makeTempDir();
  // A quarter of a 0.025 m particle's water per drop.
  expectResumedEqualsStraight(dir,
                              rainScene(0.2, R"(, "feed_fluid": true, "drop_volume": 3.90625e-6)"));
  if (HasFatalFailure()) return;
  const std::string straight = dir + "/straight.h5", resumed = dir + "/resumed.h5";
  auto run = [&](const std::string& args) {
    return runShell(test::sphsplatShell("run " + dir + "/scene.json --threads 2 -q " + args));
  };
  const io::cache::CacheReader ra(straight);
  // Rain was fed both before and after the frame the resume started from.
  const rain::FeedState half = ra.readRestart(2).first.rain, end = ra.readRestart(4).first.rain;
  EXPECT_GT(half.particles, 0u);
  EXPECT_GT(end.particles, half.particles);
  EXPECT_EQ(ra.summary().frames[4].particles, ra.summary().frames[0].particles + end.particles +
                                                  ra.readRestart(4).first.emitters[0].emitted);
  // info reports the ledger of the last frame.
  auto info = runShell(test::sphsplatShell("info " + straight));
  ASSERT_EQ(info.exitCode, 0) << info.output;
  EXPECT_NE(info.output.find("rain feed  " + std::to_string(end.landedDrops) +
                             " drops landed in the water: " + std::to_string(end.particles) +
                             " fluid particles"),
            std::string::npos)
      << info.output;
  // A different rain is a different run: the resume refuses it.
  std::ofstream(dir + "/scene.json")
      << rainScene(0.2, R"(, "feed_fluid": true, "drop_volume": 3e-6)");
  auto d = run("--end 0.3 --resume " + resumed);
  EXPECT_EQ(d.exitCode, 2) << d.output;
  EXPECT_NE(d.output.find("or its rain that feeds the fluid"), std::string::npos) << d.output;
}

}  // namespace
}  // namespace sph
