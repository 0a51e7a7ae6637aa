// Rain as a user meets it: `run` of scenes/rain_pour.json draws its pictures with rain, `render` of
// the cache regenerates the same rain pixel for pixel (docs/rain.md, "Replay"), and a bad rain key
// stops the run with one line and exit code 2.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <fstream>
#include <iterator>

#include "io/exports/Png.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

TEST(RainCli, RenderOfTheCacheDrawsTheSameRainAsTheRun) {
  const std::string dir = test::writeTempFile("", "") + "-rain";
  ::mkdir(dir.c_str(), 0755);
  const std::string small = " --set render.width=160 --set render.height=120";
  auto r =
      test::runSphsplat("run " + test::sourcePath("scenes/rain_pour.json") +
                        " --set solver.end_time=0.1 --set render.every=3" + small +
                        " --set render.directory=" + dir + "/run -q --output " + dir + "/rain.h5");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = test::runSphsplat("render " + dir + "/rain.h5 --size 160x120 -q --out " + dir + "/replay");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (std::size_t f : {0, 3}) {
    const std::string name = io::exports::framePngName("rain_pour_quad", f);
    const std::string a = slurp(dir + "/run/" + name), b = slurp(dir + "/replay/" + name);
    ASSERT_FALSE(a.empty()) << name;
    EXPECT_EQ(a, b) << name;
  }
  // Without rain the same frame is another picture.
  r = test::runSphsplat("render " + dir +
                        "/rain.h5 --size 160x120 -q --frames 3 --set rain.count=1 --out " + dir +
                        "/fewer");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string name = io::exports::framePngName("rain_pour_quad", 3);
  EXPECT_NE(slurp(dir + "/fewer/" + name), slurp(dir + "/replay/" + name));
}

TEST(RainCli, BadRainKeysStopTheRunWithOneLine) {
  const auto r = test::runSphsplat("run " + test::sourcePath("scenes/rain_pour.json") +
                                   " --set rain.far=0.01 -q");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find("rain_pour.json: rain.far: expected far > near"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
}

}  // namespace
}  // namespace sph
