#include "tests/CacheTestSupport.h"

#include <hdf5.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "io/cache/CacheFormat.h"
#include "io/cache/CacheReader.h"
#include "io/cache/RainCache.h"

namespace sph::test {

std::string tinyCacheScene(double endTime, double fps, const std::string& extraOutput) {
  std::ostringstream s;
  s.precision(17);
  s << R"({
  "name": "tiny",
  "solver": {"spacing": 0.025, "end_time": )"
    << endTime << R"(},
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.2, 0.2, 0.15]}],
  "fluids": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.15]}],
  "emitters": [{"type": "nozzle", "position": [0.15, 0.17, 0.075], "direction": [0, -1, 0], "radius": 0.02,
                "speed": 0.5, "start": 0, "stop": 1}],
  "output": {"fps": )"
    << fps << (extraOutput.empty() ? "" : ", " + extraOutput) << R"(}
}
)";
  return s.str();
}

std::string tinyRenderingScene(double endTime, double fps) {
  std::string scene = tinyCacheScene(endTime, fps);
  const std::string camera =
      R"(  "camera": {"position": [0.5, 0.4, 0.5], "target": [0.1, 0.05, 0.075], "fov": 40},
  "render": {"splat": "quad", "width": 96, "height": 64},
)";
  return scene.insert(scene.find("  \"output\""), camera);
}

std::string makeTempDir() {
  return makeTempDirectory("sphsplat-cache-test");
}

std::string sphsplatBinary() {
  return sphsplatCommand();  // with the sanitizer options a sanitizer build needs (TestSupport.h)
}

std::string preloadInto(const std::string& shim) {
#ifdef SPHSPLAT_ASAN_RUNTIME
  return std::string("LD_PRELOAD='") + SPHSPLAT_ASAN_RUNTIME + ":" + shim + "'";
#else
  return "LD_PRELOAD='" + shim + "'";
#endif
}

std::string sphsplatShell(const std::string& args) {
  return "OMP_WAIT_POLICY=PASSIVE " + sphsplatBinary() + " " + args;
}

std::size_t lineCount(const std::string& s) {
  std::size_t n = 0;
  for (char c : s) n += c == '\n';
  return n + (!s.empty() && s.back() != '\n');
}

::testing::AssertionResult sameBits(const Particles& expected, const Particles& actual) {
  // The cache lists every array of Particles in Particles' order (checked in io/cache/CacheFormat.cpp).
  static_assert(io::cache::kFieldCount == Particles::kFieldCount);
  auto name = [](std::size_t k) { return io::cache::fieldName(static_cast<io::cache::Field>(k)); };
  std::vector<std::pair<const void*, std::size_t>> a, b;
  expected.forEachField([&](const auto& f) { a.emplace_back(f.data(), f.size() * sizeof(f[0])); });
  actual.forEachField([&](const auto& f) { b.emplace_back(f.data(), f.size() * sizeof(f[0])); });
  if (expected.x.size() != actual.x.size()) {
    return ::testing::AssertionFailure()
           << "particle counts differ: " << expected.x.size() << " vs " << actual.x.size();
  }
  int compared = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].second == 0 || b[k].second == 0) continue;  // not held by one side
    if (a[k].second != b[k].second)
      return ::testing::AssertionFailure() << name(k) << ": sizes differ";
    if (std::memcmp(a[k].first, b[k].first, a[k].second) != 0) {
      return ::testing::AssertionFailure() << name(k) << ": values differ";
    }
    ++compared;
  }
  if (compared == 0 && !expected.x.empty())
    return ::testing::AssertionFailure() << "no field in common";
  return ::testing::AssertionSuccess();
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool fileExists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

void expectSameCache(const std::string& a, const std::string& b) {
  const io::cache::CacheReader ra(a), rb(b);
  ASSERT_EQ(ra.frameCount(), rb.frameCount());
  for (std::size_t k = 0; k < ra.frameCount(); ++k) {
    EXPECT_EQ(ra.summary().frames[k].time, rb.summary().frames[k].time) << "frame " << k;
    EXPECT_EQ(ra.summary().frames[k].step, rb.summary().frames[k].step) << "frame " << k;
    EXPECT_TRUE(test::sameBits(ra.readFrame(k), rb.readFrame(k))) << "frame " << k;
    const auto [sa, pa] = ra.readRestart(k);
    const auto [sb, pb] = rb.readRestart(k);
    EXPECT_TRUE(test::sameBits(pa, pb)) << "resume record " << k;
    EXPECT_EQ(sa.lastDt, sb.lastDt) << k;
    EXPECT_EQ(sa.maxSpeed, sb.maxSpeed) << k;
    EXPECT_EQ(sa.maxAcceleration, sb.maxAcceleration) << k;
    EXPECT_EQ(sa.nextId, sb.nextId) << k;
    EXPECT_EQ(sa.lostParticles, sb.lostParticles) << k;
    EXPECT_EQ(sa.rain.landedDrops, sb.rain.landedDrops) << k;
    EXPECT_EQ(sa.rain.particles, sb.rain.particles) << k;
    EXPECT_EQ(sa.rain.pending, sb.rain.pending) << k;
    EXPECT_EQ(sa.warmStart.density, sb.warmStart.density) << k;
    EXPECT_EQ(sa.warmStart.divergence, sb.warmStart.divergence) << k;
    EXPECT_EQ(sa.warmStart.wallShare, sb.warmStart.wallShare) << k;
    ASSERT_EQ(sa.emitters.size(), sb.emitters.size());
    for (std::size_t e = 0; e < sa.emitters.size(); ++e) {
      EXPECT_EQ(sa.emitters[e].travelled, sb.emitters[e].travelled);
      EXPECT_EQ(sa.emitters[e].emitted, sb.emitters[e].emitted);
    }
    // The rain's drops stored beside the frame (/Rain#N), bit for bit.
    ASSERT_EQ(ra.summary().frames[k].rainDrops, rb.summary().frames[k].rainDrops) << k;
    if (ra.summary().frames[k].rainDrops == 0) continue;
    const io::cache::RainFrame da = io::cache::readRainFrame(ra, k),
                               db = io::cache::readRainFrame(rb, k);
    EXPECT_EQ(da.time, db.time) << "rain " << k;
    ASSERT_EQ(da.positions.size(), db.positions.size()) << "rain " << k;
    EXPECT_EQ(0, std::memcmp(da.positions.data(), db.positions.data(),
                             da.positions.size() * sizeof(Vec3)))
        << "rain positions " << k;
    EXPECT_EQ(da.generations, db.generations) << "rain " << k;
    EXPECT_EQ(da.layers, db.layers) << "rain " << k;
  }
}

void TinyCacheSuite::SetUpTestSuite() {
  dir_ = makeTempDir();
  scene_ = dir_ + "/tiny.json";
  std::ofstream(scene_) << tinyCacheScene(0.1, 100);
  cache_ = dir_ + "/tiny.h5";
  runOutput_ = runShell(sphsplatShell("run '" + scene_ + "' --threads 1 -o '" + cache_ + "'"));
}
std::string TinyCacheSuite::dir_, TinyCacheSuite::scene_, TinyCacheSuite::cache_;
CommandResult TinyCacheSuite::runOutput_;

std::string hdf5ErrorStack() {
  std::string text;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        if (e->desc && *e->desc) *static_cast<std::string*>(data) += std::string(e->desc) + "; ";
        return 0;
      },
      &text);
  return text;
}

std::string plainOpenError(const std::string& path) {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_file_locking(fapl, false, true);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  const std::string failed = file < 0 ? hdf5ErrorStack() : "";  // before the next call clears it
  H5Pclose(fapl);
  if (file >= 0) H5Fclose(file);
  return failed;
}

}  // namespace sph::test
