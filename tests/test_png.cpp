// PNG files (io/exports/Png.h): what is written reads back pixel for pixel, a bad file is an
// InputError naming it, and every command names a frame's picture the same way.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "io/exports/Png.h"
#include "sim/InputError.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

TEST(Png, WhatIsWrittenReadsBack) {
  const int w = 7, h = 3;
  std::vector<std::uint8_t> rgb(3 * w * h);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(37 * i);
  const std::string path = test::writeTempFile("", ".png");
  io::exports::writePng(path, w, h, rgb.data());
  int rw = 0, rh = 0;
  EXPECT_EQ(io::exports::readPng(path, rw, rh), rgb);
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  std::remove(path.c_str());
}

TEST(Png, ANonPngFileIsAnInputErrorNamingIt) {
  const std::string path = test::writeTempFile("not a picture", ".png");
  int w = 0, h = 0;
  try {
    io::exports::readPng(path, w, h);
    FAIL() << "read a text file as a PNG";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(FramePngName, IsTheStemAndFiveDigits) {
  EXPECT_EQ(io::exports::framePngName("pour_quad", 12), "pour_quad_00012.png");
  EXPECT_EQ(io::exports::framePngName("dam_break_compare", 0), "dam_break_compare_00000.png");
  EXPECT_EQ(io::exports::framePngName("x", 123456), "x_123456.png");  // more digits, never cut
  const std::string longStem(200, 's');
  EXPECT_EQ(io::exports::framePngName(longStem, 7), longStem + "_00007.png");
}

}  // namespace
}  // namespace sph
