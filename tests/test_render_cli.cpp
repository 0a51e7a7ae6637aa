// The renderer's commands as a user meets them: `compare` writes its picture and numbers,
// `render` writes PNGs (and into the cache), `view` opens a window under Xvfb whose screenshot
// is not blank and changes with the splat mode, and bad input gets one line and exit code 2.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdlib>
#include <regex>

#include "io/exports/Png.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using test::runSphsplat;

bool exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

// A small cache of the shipped dam break (it has a camera), made once for the suite.
class RenderCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::writeTempFile("", "") + "-dir";
    ::mkdir(dir_.c_str(), 0755);
    const auto r =
        runSphsplat("run " + test::sourcePath("scenes/dam_break.json") +
                    " --set solver.spacing=0.012 --end 0.1 -q --output " + dir_ + "/dam.h5");
    ASSERT_EQ(r.exitCode, 0) << r.output;
  }
  static std::string cache() { return dir_ + "/dam.h5"; }
  static std::string dir_;
};
std::string RenderCli::dir_;

TEST_F(RenderCli, CompareWritesThePanelsAndTheNumbers) {
  const auto r = runSphsplat("compare " + cache() + " --frame last --size 320x240 --out " + dir_ +
                             " --set render.projection=newton");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::smatch m;
  const std::regex point(
      "point +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ \\| +([0-9.]+) +([0-9.]+) +([0-9.]+)");
  const std::regex quad(
      "quad +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ \\| +([0-9.]+) +([0-9.]+) +([0-9.]+)");
  ASSERT_TRUE(std::regex_search(r.output, m, point)) << r.output;
  const double pointPsnr = std::stod(m[1]), pointNormal = std::stod(m[3]);
  ASSERT_TRUE(std::regex_search(r.output, m, quad)) << r.output;
  const double quadPsnr = std::stod(m[1]), quadNormal = std::stod(m[3]);
  // The point of the paper: per-vertex normals on the iso-surface beat one normal per square.
  EXPECT_GT(quadPsnr, pointPsnr);
  EXPECT_LT(quadNormal, pointNormal);
  // The particles' balls beyond the SD surface, and how much of them each kind draws.
  const std::regex beyond(
      "beyond the SD surface .*: ([0-9]+) pixels of particle balls; point splats cover "
      "([0-9.]+)%, quad ([0-9.]+)%");
  ASSERT_TRUE(std::regex_search(r.output, m, beyond)) << r.output;
  EXPECT_GT(std::stoul(m[1]), 0u);
  EXPECT_LE(std::stod(m[3]), 100.0);
  int w = 0, h = 0;
  const auto rgb = io::exports::readPng(dir_ + "/dam_break_compare_00006.png", w, h);
  EXPECT_GT(w, 2 * 320);  // point | quad over reference | particles
  EXPECT_GT(h, 2 * 240);  // with captions below each
}

TEST_F(RenderCli, CompareSaysHowManySplatsItDrewAndBackFacesCanBeKept) {
  const std::regex header("([0-9]+) surface \\(SD = [0-9.]+ x ID\\), ([0-9]+) splats drawn");
  std::smatch m;
  const auto culled =
      runSphsplat("compare " + cache() + " --frame last --size 160x120 --out " + dir_);
  ASSERT_EQ(culled.exitCode, 0) << culled.output;
  ASSERT_TRUE(std::regex_search(culled.output, m, header)) << culled.output;
  EXPECT_LT(std::stoul(m[2]), std::stoul(m[1]));  // the default drops those facing away
  const auto all = runSphsplat("compare " + cache() + " --frame last --size 160x120 --out " + dir_ +
                               " --set render.cull_back_faces=false");
  ASSERT_EQ(all.exitCode, 0) << all.output;
  ASSERT_TRUE(std::regex_search(all.output, m, header)) << all.output;
  EXPECT_EQ(std::stoul(m[2]), std::stoul(m[1]));
}

TEST_F(RenderCli, RenderWritesPngsAndStoresThemInTheCache) {
  const auto r =
      runSphsplat("render " + cache() +
                  " --frames 1:2 --splat both --size 160x120 --to-cache --out " + dir_ + "/frames");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* kind : {"point", "quad"}) {
    for (std::size_t f : {1, 2}) {
      const std::string name = io::exports::framePngName(std::string("dam_break_") + kind, f);
      EXPECT_TRUE(exists(dir_ + "/frames/" + name)) << name;
    }
  }
  EXPECT_FALSE(exists(dir_ + "/frames/dam_break_quad_00000.png"));
  const auto info = runSphsplat("info " + cache());
  EXPECT_NE(info.output.find("point"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("quad"), std::string::npos) << info.output;
}

TEST_F(RenderCli, BadInputIsOneLineAndExitTwo) {
  const auto missing = runSphsplat("render /nonexistent/x.h5");
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_NE(missing.output.find("/nonexistent/x.h5"), std::string::npos) << missing.output;
  const auto range = runSphsplat("render " + cache() + " --frames 99");
  EXPECT_EQ(range.exitCode, 2);
  EXPECT_NE(range.output.find("--frames: frames 99 are not in the cache (it has frames 0 to 6)"),
            std::string::npos)
      << range.output;
  const auto backwards = runSphsplat("render " + cache() + " --frames 5:2");
  EXPECT_EQ(backwards.exitCode, 2);
  EXPECT_NE(backwards.output.find(
                "--frames: frames 5:2 run backwards (write the first frame first, 2:5)"),
            std::string::npos)
      << backwards.output;
  const auto size = runSphsplat("compare " + cache() + " --size 10x10");
  EXPECT_EQ(size.exitCode, 2);
  EXPECT_NE(size.output.find("--size: expected WIDTHxHEIGHT"), std::string::npos) << size.output;
  // One frame syntax for every subcommand; compare takes one frame, not the first of a range.
  const auto several = runSphsplat("compare " + cache() + " --frame 2:5");
  EXPECT_EQ(several.exitCode, 2);
  EXPECT_EQ(several.output,
            "sphsplat: --frame: expected one frame (an index, 'last' or -1), got the range "
            "'2:5'\n");
}

// A frame's PNG is redrawn over an older PNG, never over a device node or FIFO.
TEST_F(RenderCli, FramesAreNeverWrittenOverNonRegularFiles) {
  const std::string out = dir_ + "/fifo-frames";
  ::mkdir(out.c_str(), 0755);
  const std::string fifo = out + "/dam_break_point_00001.png";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
  const auto r =
      runSphsplat("render " + cache() + " --frames 0:1 --splat point --size 64x48 -q --out " + out);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(r.output, "sphsplat: " + fifo +
                          ": is a FIFO (named pipe), not a regular file; refusing to replace it "
                          "with an image\n");
  struct stat st {};
  ASSERT_EQ(lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_TRUE(exists(out + "/dam_break_point_00000.png")) << "frame 0 is drawn";
  // All of a cache's frames, by the word.
  const auto all = runSphsplat("render " + cache() +
                               " --frames all --splat point --size 64x48 "
                               "-q --out " +
                               dir_ + "/all");
  EXPECT_EQ(all.exitCode, 0) << all.output;
  EXPECT_TRUE(exists(dir_ + "/all/dam_break_point_00006.png"));
}

// A full disk (here a file size limit, which fails writes the same way) while a picture is
// written: one line naming the picture and why, not libpng's own second line, and no half PNG.
TEST_F(RenderCli, AFullDiskWhileAPictureIsWrittenIsOneLine) {
  const std::string out = dir_ + "/full-frames";
  const auto r = test::runShell("sh -c \"ulimit -f 1; trap '' XFSZ; exec " +
                                test::sphsplatCommand() + " render " + cache() +
                                " --frames 0 --splat point --size 160x120 -q --out " + out +
                                "\" 2>&1");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(r.output, "sphsplat: " + out +
                          "/dam_break_point_00000.png: cannot write the image (libpng: Write "
                          "Error: File too large)\n");
  EXPECT_FALSE(exists(out + "/dam_break_point_00000.png"));
}

// Fraction of pixels of a PNG that differ from its top-left pixel (the background).
double nonBackground(const std::string& path) {
  int w = 0, h = 0;
  const auto rgb = io::exports::readPng(path, w, h);
  std::size_t n = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(w) * h; ++p) {
    n += rgb[3 * p] != rgb[0] || rgb[3 * p + 1] != rgb[1] || rgb[3 * p + 2] != rgb[2];
  }
  return static_cast<double>(n) / (static_cast<double>(w) * h);
}

TEST_F(RenderCli, ViewerWindowUnderXvfbShowsTheFluidAndSwitchesModes) {
  if (std::system("command -v xvfb-run > /dev/null") != 0) GTEST_SKIP() << "xvfb-run not installed";
  std::string shots[2];
  const char* modes[2] = {"point", "quad"};
  for (int k = 0; k < 2; ++k) {
    shots[k] = dir_ + "/view_" + modes[k] + ".png";
    const std::string command = std::string("xvfb-run -a -s '-screen 0 800x600x24' ") +
                                test::sphsplatCommand() + " view " + cache() +
                                " --frame last --width 400 --height 300 --exit-after 2 --splat " +
                                modes[k] + " --screenshot " + shots[k] + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    ASSERT_TRUE(exists(shots[k]));
    EXPECT_GT(nonBackground(shots[k]), 0.05) << shots[k] << " is blank";
  }
  int w = 0, h = 0;
  EXPECT_NE(io::exports::readPng(shots[0], w, h), io::exports::readPng(shots[1], w, h))
      << "switching the splat mode changed nothing";
  // The frame and time are drawn on the picture: a dark box with light text at the top left.
  const std::vector<std::uint8_t> rgb = io::exports::readPng(shots[1], w, h);
  int box = 0, text = 0;
  for (int y = 8; y < 40; ++y) {
    for (int x = 8; x < 120; ++x) {
      const std::uint8_t* p = &rgb[3 * (static_cast<std::size_t>(y) * w + x)];
      box += p[0] == 22 && p[1] == 26 && p[2] == 34;
      text += p[0] > 230 && p[1] > 230 && p[2] > 230;
    }
  }
  EXPECT_GT(box, 1000) << "no status box";
  EXPECT_GT(text, 100) << "no text in the status box";
}

}  // namespace
}  // namespace sph
