// The rain's CPU streak rasteriser (render/rain/StreakRaster.h, rain.draw "cpu") on its own, CPU
// only: the same layer for any thread count and with or without SIMD lanes, the depth test, and
// the level of detail (rain.lod_width, rain.far_tier) against the exact streaks. The rasteriser
// against GL's triangles is test_rain_raster_gl; the sums and the composite test_rain_sums.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "render/rain/StreakRaster.h"
#include "sim/rain/RainSystem.h"
#include "sim/scene/Camera.h"
#include "tests/RainRasterScenes.h"
#include "tests/RainTruth.h"

namespace sph::render::rain {
namespace {

using test::streaks::camera;
using test::streaks::desc;
using test::streaks::kAspect;
using test::streaks::kHeight;
using test::streaks::kWidth;

// rain.lod_width 0 (every streak exact), 1 with rain.far_tier "lines" (the lines of the level of
// detail) and 1 and 4 with "sums" (render/rain/StreakSums.h; 4: streaks up to 4 pixels wide as
// lines side by side).
struct Lod {
  float width;
  scene::RainFarTier farTier;
};
class StreakRasterLod : public ::testing::TestWithParam<Lod> {
 protected:
  scene::RainDesc lodDesc(std::size_t count) const {
    scene::RainDesc d = desc(count, scene::RainDraw::Cpu);
    d.lodWidth = GetParam().width, d.farTier = GetParam().farTier;
    return d;
  }
};
INSTANTIATE_TEST_SUITE_P(LodWidth, StreakRasterLod,
                         ::testing::Values(Lod{0.0f, scene::RainFarTier::Lines},
                                           Lod{1.0f, scene::RainFarTier::Lines},
                                           Lod{1.0f, scene::RainFarTier::Sums},
                                           Lod{4.0f, scene::RainFarTier::Sums}));

TEST_P(StreakRasterLod, TheLayerIsTheSameBitForBitForAnyThreadCount) {
  const scene::RainDesc d = lodDesc(20000);
  sph::rain::RainSystem drops(d, kAspect);
  drops.reset(camera());
  // A depth buffer with a near wall over the left third, so the depth test takes part.
  std::vector<float> depth(static_cast<std::size_t>(kWidth) * kHeight, 1.0f);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth / 3; ++x) depth[static_cast<std::size_t>(y) * kWidth + x] = 0.9f;
  const StreakView view{cameraFrame(camera(), kAspect), kWidth, kHeight};
  const StreakDrops input{&drops.positions(), &drops.layers(), drops.velocity()};
  const int threads = omp_get_max_threads();
  std::vector<float> first;
  std::uint64_t firstFragments = 0;
  for (int t : {1, 2, 3, 7}) {
    omp_set_num_threads(t);
    StreakRaster raster(d, generateStreakImages(d.streakLayers, 16, 64, d.seed));
    raster.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), depth.data());
    if (first.empty()) {
      first = raster.layer(), firstFragments = raster.fragments();
      EXPECT_GT(firstFragments, 20000u);
      continue;
    }
    EXPECT_EQ(raster.fragments(), firstFragments) << t << " threads";
    EXPECT_TRUE(raster.layer() == first) << t << " threads";
  }
  omp_set_num_threads(threads);
}

// The lines of the level of detail drawn 16 rows at a time in AVX-512 lanes against one row at a
// time (render/rain/StreakLine.cpp): the same layer bit for bit, both for streaks slanted by the
// wind and seen from above (a step of 16 rows spans several columns: blended row by row) and for
// rain falling straight down before a level camera (one column: blended in lanes). Where the build
// has no AVX-512 both are the row-at-a-time path.
TEST(StreakRaster, LinesInSimdLanesGiveTheSameLayerAsOneRowAtATime) {
  for (const bool slanted : {true, false}) {
    scene::RainDesc d = desc(20000, scene::RainDraw::Cpu);
    d.lodWidth = 1, d.farTier = scene::RainFarTier::Lines;
    scene::CameraDesc c = camera();
    if (!slanted) d.wind = Vec3::Zero(), c.target = Vec3(c.position.x(), c.position.y(), 0);
    sph::rain::RainSystem drops(d, kAspect);
    drops.reset(c);
    // A near wall over the left third and a slope over the rest: lines cut by the depth test.
    std::vector<float> depth(static_cast<std::size_t>(kWidth) * kHeight, 1.0f);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        depth[static_cast<std::size_t>(y) * kWidth + x] =
            x < kWidth / 3 ? 0.9f : 0.97f + 0.03f * static_cast<float>(y) / kHeight;
    const StreakView view{cameraFrame(c, kAspect), kWidth, kHeight};
    const StreakDrops input{&drops.positions(), &drops.layers(), drops.velocity()};
    StreakRaster lanes(d, generateStreakImages(d.streakLayers, 16, 64, d.seed));
    StreakRaster rows(d, generateStreakImages(d.streakLayers, 16, 64, d.seed));
    rows.setSimd(false);
    lanes.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), depth.data());
    rows.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), depth.data());
    EXPECT_GT(rows.fragments(), 20000u) << slanted;
    EXPECT_LT(rows.fragments(), 20000u * 60) << slanted;  // some cut by the depth
    EXPECT_EQ(lanes.fragments(), rows.fragments()) << slanted;
    EXPECT_TRUE(lanes.layer() == rows.layer()) << slanted;
  }
}

TEST_P(StreakRasterLod, NothingIsDrawnBehindTheDepthAndEverythingInFrontOfIt) {
  const scene::RainDesc d = lodDesc(2000);
  sph::rain::RainSystem drops(d, kAspect);
  drops.reset(camera());
  const StreakView view{cameraFrame(camera(), kAspect), kWidth, kHeight};
  const StreakDrops input{&drops.positions(), &drops.layers(), drops.velocity()};
  StreakRaster raster(d, generateStreakImages(d.streakLayers, 16, 64, d.seed));
  std::vector<float> depth(static_cast<std::size_t>(kWidth) * kHeight, 0.0f);
  raster.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), depth.data());
  EXPECT_EQ(raster.fragments(), 0u);
  for (std::size_t i = 0; i < raster.layer().size(); ++i)
    ASSERT_EQ(raster.layer()[i], i % 4 == 3 ? 1.0f : 0.0f) << i;
  std::fill(depth.begin(), depth.end(), 1.0f);
  raster.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), depth.data());
  const std::uint64_t all = raster.fragments();
  raster.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), nullptr);
  EXPECT_GT(all, 2000u);
  EXPECT_EQ(raster.fragments(), all);
}

// A depth of 0 (nothing drawn in front of it) on every other pixel, a checkerboard, and 1 on the
// rest: every streak meets hidden pixels in every column, so the sums take their depth test row
// by row. The hidden pixels stay exactly as they were, and every other pixel is bit for bit what
// it is without them - a pixel's layer depends only on the fragments at that pixel, for every
// tier (the sums too: each pixel's running sum holds the lines over it and no other).
TEST_P(StreakRasterLod, HiddenPixelsStayAsTheyWereAndHideNothingElse) {
  const scene::RainDesc d = lodDesc(20000);
  sph::rain::RainSystem drops(d, kAspect);
  drops.reset(camera());
  const StreakView view{cameraFrame(camera(), kAspect), kWidth, kHeight};
  const StreakDrops input{&drops.positions(), &drops.layers(), drops.velocity()};
  std::vector<float> depth(static_cast<std::size_t>(kWidth) * kHeight, 1.0f);
  for (int y = 0; y < kHeight; ++y)
    for (int x = (y & 1); x < kWidth; x += 2) depth[static_cast<std::size_t>(y) * kWidth + x] = 0;
  StreakRaster open(d, generateStreakImages(d.streakLayers, 16, 64, d.seed));
  StreakRaster hidden(d, generateStreakImages(d.streakLayers, 16, 64, d.seed));
  open.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), nullptr);
  hidden.draw(view, input, Vec3(0.4f, 0.45f, 0.5f), depth.data());
  EXPECT_GT(hidden.fragments(), open.fragments() / 3);
  EXPECT_LT(hidden.fragments(), open.fragments() * 2 / 3);
  int lit = 0;
  for (std::size_t p = 0; p < depth.size(); ++p)
    for (int k = 0; k < 4; ++k) {
      const float expected = depth[p] == 0 ? (k == 3 ? 1.0f : 0.0f) : open.layer()[4 * p + k];
      ASSERT_EQ(hidden.layer()[4 * p + k], expected) << p << " " << k;
      lit += depth[p] != 0 && k == 3 && expected < 1;
    }
  EXPECT_GT(lit, kWidth * kHeight / 8);  // the rain is there to compare
}

// The level of detail against the exact streaks (docs/rain.md, "Level of detail"): the same
// drops over a mid-grey frame, 8-bit sRGB values. The lines spread a streak's light over every
// row instead of the rows whose pixel centre it happens to cover, so single pixels differ by up
// to a streak's full alpha; the light in total stays the same and the picture stays close.
TEST(StreakRaster, LevelOfDetailKeepsTheLightAndStaysCloseToTheExactStreaks) {
  scene::RainDesc d = desc(20000, scene::RainDraw::Cpu);
  d.spotlight.reset();  // one colour: the light in total compares as one number
  sph::rain::RainSystem drops(d, kAspect);
  drops.reset(camera());
  const StreakView view{cameraFrame(camera(), kAspect), kWidth, kHeight};
  const StreakDrops input{&drops.positions(), &drops.layers(), drops.velocity()};
  auto frame = [&](float lodWidth, scene::RainFarTier farTier, std::uint64_t& fragments) {
    scene::RainDesc e = d;
    e.lodWidth = lodWidth, e.farTier = farTier;
    StreakRaster raster(e, generateStreakImages(e.streakLayers, 16, 64, e.seed));
    raster.draw(view, input, Vec3(0.9f, 0.9f, 0.9f), nullptr);
    fragments = raster.fragments();
    std::vector<double> out;
    for (std::size_t i = 0; i < raster.layer().size(); i += 4)
      for (int c = 0; c < 3; ++c)
        out.push_back(std::round(255 * (raster.layer()[i + c] + raster.layer()[i + 3] * 0.5f)));
    return out;
  };
  std::uint64_t exactFragments = 0;
  const std::vector<double> exact = frame(0, scene::RainFarTier::Lines, exactFragments);
  for (const Lod& level :
       {Lod{0.5f, scene::RainFarTier::Lines}, Lod{1.0f, scene::RainFarTier::Lines},
        Lod{0.5f, scene::RainFarTier::Sums}, Lod{1.0f, scene::RainFarTier::Sums},
        Lod{2.0f, scene::RainFarTier::Sums}, Lod{4.0f, scene::RainFarTier::Sums}}) {
    const float lodWidth = level.width;
    const bool sums = level.farTier == scene::RainFarTier::Sums;
    std::uint64_t fragments = 0;
    const std::vector<double> lod = frame(lodWidth, level.farTier, fragments);
    double mse = 0, worst = 0, lightExact = 0, lightLod = 0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      mse += (lod[i] - exact[i]) * (lod[i] - exact[i]);
      worst = std::max(worst, std::abs(lod[i] - exact[i]));
      lightExact += exact[i] - 128, lightLod += lod[i] - 128;
    }
    mse /= static_cast<double>(exact.size());
    // The same over blocks of 4 x 4 pixels, averaged: the picture at a scale of a few pixels.
    double blockMse = 0;
    int blocks = 0;
    for (int by = 0; by + 4 <= kHeight; by += 4)
      for (int bx = 0; bx + 4 <= kWidth; bx += 4)
        for (int c = 0; c < 3; ++c) {
          double diff = 0;
          for (int y = by; y < by + 4; ++y)
            for (int x = bx; x < bx + 4; ++x) {
              const std::size_t i = 3 * (static_cast<std::size_t>(y) * kWidth + x) + c;
              diff += (lod[i] - exact[i]) / 16;
            }
          blockMse += diff * diff, ++blocks;
        }
    blockMse /= blocks;
    const double psnr = 10 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
    const double blockPsnr = 10 * std::log10(255.0 * 255.0 / std::max(blockMse, 1e-12));
    std::printf(
        "lod_width %.1f, far_tier %s: PSNR %.1f dB (4x4 blocks: %.1f dB), worst %.0f of 255, light "
        "%.4f of the exact's, fragments %llu against %llu\n",
        lodWidth, nameOf(level.farTier), psnr, blockPsnr, worst, lightLod / lightExact,
        static_cast<unsigned long long>(fragments),
        static_cast<unsigned long long>(exactFragments));
    // Bounds a little under what was measured (docs/rain.md, "Level of detail"): the sums of
    // streaks wider than a pixel (lod_width 2, 4) draw the nearest, brightest streaks as lines
    // side by side too, and with their mean along the streak: 1-2 dB further from the exact.
    const bool wide = lodWidth > 1;
    EXPECT_NEAR(lightLod / lightExact, 1.0, 0.01) << lodWidth << " " << sums;
    EXPECT_GT(psnr, lodWidth < 0.75f ? 27.0 : wide ? 21.0 : 22.0) << lodWidth << " " << sums;
    EXPECT_GT(blockPsnr, lodWidth < 0.75f ? 40.0 : wide ? 34.5 : 36.0) << lodWidth << " " << sums;
    EXPECT_LE(worst, lodWidth < 0.75f ? 90.0 : 110.0) << lodWidth << " " << sums;
    // every row of a line, not ~its width
    EXPECT_GT(fragments, exactFragments) << lodWidth << " " << sums;
  }
}

// The default drawing (scene::RainDesc's rain.far_tier and rain.lod_width, the sums at 8 since
// 2026-11-29) against the true picture (tests/RainTruth.h: the exact streaks at 4x the
// resolution, box-filtered): at least as close to it as the exact streaks at 1x, whose streaks
// narrower than a pixel are dotted lines of full-alpha pixels. Over the test camera's slanted,
// partly spotlit rain at two budgets.
TEST(StreakRaster, TheDefaultIsCloserToTheTruePictureThanTheExactStreaks) {
  const std::uint8_t background[3] = {188, 192, 200};
  const Vec3 unlit(0.4f, 0.45f, 0.5f);
  for (const std::size_t count : {std::size_t{5000}, std::size_t{50000}}) {
    scene::RainDesc d = desc(count, scene::RainDraw::Cpu);
    sph::rain::RainSystem drops(d, kAspect);
    drops.reset(camera());
    const scene::CameraFrame c = cameraFrame(camera(), kAspect);
    const std::vector<double> truth = test::truth::reference(d, test::truth::dropsOf(drops), c,
                                                             kWidth, kHeight, 4, unlit, background);
    const std::vector<double> exact = test::truth::frame(d, test::truth::dropsOf(drops), c, kWidth,
                                                         kHeight, 1, unlit, background);
    d.lodWidth = scene::RainDesc{}.lodWidth, d.farTier = scene::RainDesc{}.farTier;
    const std::vector<double> lod = test::truth::frame(d, test::truth::dropsOf(drops), c, kWidth,
                                                       kHeight, 1, unlit, background);
    const double psnrExact = test::truth::psnr(exact, truth),
                 psnrLod = test::truth::psnr(lod, truth);
    const double lightRatio =
        test::truth::light(lod, background) / test::truth::light(truth, background);
    std::printf(
        "%zu drops: PSNR against the true picture: exact %.2f dB, default (%s %.0f) %.2f dB; "
        "light %.4f of the true picture's (exact: %.4f)\n",
        count, psnrExact, nameOf(d.farTier), static_cast<double>(d.lodWidth), psnrLod, lightRatio,
        test::truth::light(exact, background) / test::truth::light(truth, background));
    EXPECT_GT(psnrLod, psnrExact) << count;
    EXPECT_NEAR(lightRatio, 1.0, 0.02) << count;
  }
}

}  // namespace
}  // namespace sph::render::rain
