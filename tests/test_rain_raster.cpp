// The rain's CPU streak rasteriser (render/rain/StreakRaster.h, rain.draw "cpu"): the same layer
// for any thread count (CPU only); and on llvmpipe, against the GL triangles of rain.draw
// "triangles": the same pixels within rounding, the same fragment count, and drops behind a solid
// hidden by the depth test while those in front of it show.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#if defined(__AVX512F__)
// GCC 12 warns of the `_mm512_undefined_*()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "render/gl/GlContext.h"
#include "render/gl/GlHandle.h"
#include "render/rain/ComposeOver.h"
#include "render/rain/ExpNear.h"
#include "render/rain/RainRenderer.h"
#include "render/rain/StreakRaster.h"
#include "render/rain/StreakSums.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/scene/Camera.h"
#include "sim/rain/RainSystem.h"

namespace sph::render::rain {
namespace {

constexpr int kWidth = 192, kHeight = 108;
constexpr float kAspect = static_cast<float>(kWidth) / kHeight;

// Above and to the right of the rain, looking down on it a little: no axis of the picture is an
// axis of the world.
CameraDesc camera() {
  CameraDesc c;
  c.position = Vec3(0.6f, 1.6f, 4), c.target = Vec3(0, 1, 0);
  c.fovYDegrees = 50;
  return c;
}

// Rain of the view model in front of camera(), slanted by a wind, lit in part by a soft-edged
// spotlight so that the drops' colours differ.
RainDesc desc(std::size_t count, RainDraw draw) {
  RainDesc d;
  d.count = count;
  d.near = 0.5f, d.far = 4;
  d.dropWidth = 0.01f;
  d.exposure = 0.03f;
  d.wind = Vec3(2, 0, 0);
  d.seed = 7;
  d.draw = draw;
  SpotlightDesc l;
  l.position = Vec3(-0.8f, 4, 2), l.height = 5, l.baseRadius = 2;
  l.colour = Vec3(1, 0.3f, 0.1f), l.softEdge = 0.3f;
  d.spotlight = l;
  return d;
}

// rain.lod_width 0 (every streak exact), 1 with rain.far_tier "lines" (the lines of the level of
// detail) and 1 and 4 with "sums" (render/rain/StreakSums.h; 4: streaks up to 4 pixels wide as
// lines side by side).
struct Lod {
  float width;
  RainFarTier farTier;
};
class StreakRasterLod : public ::testing::TestWithParam<Lod> {
 protected:
  RainDesc lodDesc(std::size_t count) const {
    RainDesc d = desc(count, RainDraw::Cpu);
    d.lodWidth = GetParam().width, d.farTier = GetParam().farTier;
    return d;
  }
};
INSTANTIATE_TEST_SUITE_P(LodWidth, StreakRasterLod,
                         ::testing::Values(Lod{0.0f, RainFarTier::Lines},
                                           Lod{1.0f, RainFarTier::Lines},
                                           Lod{1.0f, RainFarTier::Sums},
                                           Lod{4.0f, RainFarTier::Sums}));

TEST_P(StreakRasterLod, TheLayerIsTheSameBitForBitForAnyThreadCount) {
  const RainDesc d = lodDesc(20000);
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
    RainDesc d = desc(20000, RainDraw::Cpu);
    d.lodWidth = 1;
    CameraDesc c = camera();
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
  const RainDesc d = lodDesc(2000);
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
  const RainDesc d = lodDesc(20000);
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
  RainDesc d = desc(20000, RainDraw::Cpu);
  d.spotlight.reset();  // one colour: the light in total compares as one number
  sph::rain::RainSystem drops(d, kAspect);
  drops.reset(camera());
  const StreakView view{cameraFrame(camera(), kAspect), kWidth, kHeight};
  const StreakDrops input{&drops.positions(), &drops.layers(), drops.velocity()};
  auto frame = [&](float lodWidth, RainFarTier farTier, std::uint64_t& fragments) {
    RainDesc e = d;
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
  const std::vector<double> exact = frame(0, RainFarTier::Lines, exactFragments);
  for (const Lod& level :
       {Lod{0.5f, RainFarTier::Lines}, Lod{1.0f, RainFarTier::Lines}, Lod{0.5f, RainFarTier::Sums},
        Lod{1.0f, RainFarTier::Sums}, Lod{2.0f, RainFarTier::Sums}, Lod{4.0f, RainFarTier::Sums}}) {
    const float lodWidth = level.width;
    const bool sums = level.farTier == RainFarTier::Sums;
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

class RainRasterGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

// The frame of `d`'s drops (none: count 0) over a light sky, with `solids` (may be empty), and
// the fragments the rain drew (GL's count for the triangles, the rasteriser's for "cpu").
struct Frame {
  splat::RenderImage image;
  std::uint64_t fragments = 0;
};
Frame drawFrame(const RainDesc& d, const std::vector<BoundaryShape>& solids) {
  sph::rain::RainSystem drops(d, kAspect);
  drops.reset(camera());
  RainRenderer layer(d);
  layer.setDrops(drops);
  splat::SplatRenderer r(kWidth, kHeight);
  std::unique_ptr<solids::SolidRenderer> solid;
  std::vector<splat::FrameLayer*> layers;
  if (!solids.empty()) {
    solid = std::make_unique<solids::SolidRenderer>(solids, Aabb{Vec3(-9, -9, -9), Vec3(9, 9, 9)},
                                                    0.01f);
    layers.push_back(solid.get());
  }
  if (d.count > 0) layers.push_back(&layer);
  r.setLayers(layers);
  Frame f;
  auto query = gl::Query::create(GL_SAMPLES_PASSED);
  if (!layer.raster()) glBeginQuery(GL_SAMPLES_PASSED, query.id());
  f.image = r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera(), splat::Lighting{});
  if (layer.raster()) {
    f.fragments = layer.raster()->fragments();
  } else {
    glEndQuery(GL_SAMPLES_PASSED);
    GLuint64 n = 0;
    glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &n);
    f.fragments = n;
  }
  return f;
}

// The CPU path against the triangles on the same drops: the pixels GL fills are those whose
// centre is in the quad, which the rasteriser reproduces; what differs is rounding (GL rounds the
// RGBA8 frame after each blend, the rasteriser once; its bilinear weights are 8-bit) and the
// rare pixel centre on a quad's edge.
TEST_F(RainRasterGl, TheCpuPathDrawsTheTrianglesPictureWithinRounding) {
  const Frame cpu = drawFrame(desc(3000, RainDraw::Cpu), {});
  const Frame triangles = drawFrame(desc(3000, RainDraw::Triangles), {});
  const Frame sky = drawFrame(desc(0, RainDraw::Triangles), {});
  double squared = 0;
  int worst = 0, over8 = 0, streakPixels = 0;
  for (std::size_t i = 0; i < cpu.image.rgb.size(); ++i) {
    const int diff = std::abs(int(cpu.image.rgb[i]) - int(triangles.image.rgb[i]));
    squared += diff * diff;
    worst = std::max(worst, diff);
    over8 += diff > 8;
    streakPixels += triangles.image.rgb[i] != sky.image.rgb[i];
  }
  const double mse = squared / static_cast<double>(cpu.image.rgb.size());
  const double psnr = 10 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
  std::printf(
      "fragments cpu %llu, triangles %llu; PSNR %.1f dB, worst %d, %d of %d values "
      "off by > 8 (%d values show rain)\n",
      static_cast<unsigned long long>(cpu.fragments),
      static_cast<unsigned long long>(triangles.fragments), psnr, worst, over8,
      static_cast<int>(cpu.image.rgb.size()), streakPixels);
  EXPECT_GT(streakPixels, 5000);  // the rain is there to compare
  EXPECT_NEAR(static_cast<double>(cpu.fragments), static_cast<double>(triangles.fragments),
              0.01 * static_cast<double>(triangles.fragments));
  EXPECT_GT(psnr, 45.0);
  EXPECT_LT(over8, streakPixels / 200);
}

// A wall over the left half of the picture, between the camera and the rain: the drops behind
// it leave its pixels exactly as they were and show beside it; drops in front of it show on it.
class RainBehindASolid : public ::testing::TestWithParam<RainDraw> {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};
INSTANTIATE_TEST_SUITE_P(Draw, RainBehindASolid,
                         ::testing::Values(RainDraw::Cpu, RainDraw::Triangles),
                         [](const auto& p) { return std::string(nameOf(p.param)); });

TEST_P(RainBehindASolid, IsHiddenWhereTheSolidIsAndShowsBesideIt) {
  BoundaryShape wall;
  wall.kind = BoundaryShape::Kind::Block;
  wall.lo = Vec3(-5, -5, 1.9f), wall.hi = Vec3(0, 5, 2);
  auto rain = [&](float zLo, float zHi) {
    RainDesc d = desc(4000, GetParam());
    d.spotlight.reset();
    d.spawn = RainSpawn::Region;
    d.region.lo = Vec3(-2, -0.5f, zLo), d.region.hi = Vec3(2, 2.5f, zHi);
    return d;
  };
  const splat::RenderImage solidOnly = drawFrame(desc(0, GetParam()), {wall}).image;
  const splat::RenderImage sky = drawFrame(desc(0, GetParam()), {}).image;
  const splat::RenderImage behind = drawFrame(rain(0, 1.5f), {wall}).image;
  const splat::RenderImage inFront = drawFrame(rain(2.3f, 3), {wall}).image;
  int wallPixels = 0, changedOnWall = 0, changedBeside = 0, inFrontOnWall = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(kWidth) * kHeight; ++p) {
    bool onWall = false, b = false, f = false;
    for (int k = 0; k < 3; ++k) {
      onWall = onWall || solidOnly.rgb[3 * p + k] != sky.rgb[3 * p + k];
      b = b || behind.rgb[3 * p + k] != solidOnly.rgb[3 * p + k];
      f = f || inFront.rgb[3 * p + k] != solidOnly.rgb[3 * p + k];
    }
    wallPixels += onWall;
    changedOnWall += onWall && b;
    changedBeside += !onWall && b;
    inFrontOnWall += onWall && f;
  }
  std::printf(
      "wall %d pixels: rain behind changed %d of them and %d beside; rain in front "
      "changed %d on it\n",
      wallPixels, changedOnWall, changedBeside, inFrontOnWall);
  EXPECT_GT(wallPixels, kWidth * kHeight / 3);
  EXPECT_EQ(changedOnWall, 0);
  EXPECT_GT(changedBeside, 1000);
  EXPECT_GT(inFrontOnWall, 1000);
}

// addLines() is add() for each line, set up in groups: also for a slanted line that starts in
// column 0 and leaves the frame on the left within the same column's width (x in (-1, 0) once
// truncated is column 0, yet those rows are off the frame: review of 2026-11-27).
TEST(StreakSums, ALineLeavingTheFrameOnTheLeftAddsOnlyItsRowsInside) {
  constexpr int kW = 8, kH = 40;
  const std::vector<float> depth(kW * kH, 1.0f);
  Lines lines{};
  lines.xt[0] = 0.6f, lines.yt[0] = 10, lines.zt[0] = 0.5f, lines.dx[0] = -1, lines.dz[0] = 0;
  lines.invDy[0] = 1.0f / 20, lines.coverage[0] = 0.5f;
  lines.first[0] = 10, lines.end[0] = 30, lines.ok[0] = 1;
  const Vec3 colour(0.8f, 0.6f, 0.4f);
  const float alpha = 0.25f;
  auto layerOf = [&](bool grouped, std::uint64_t& fragments) {
    StreakSums sums;
    sums.begin(kW, kH, depth.data(), 1);
    fragments = grouped ? sums.addLines(0, lines, 1, &colour, &alpha)
                        : sums.add(0, lines[0], 10, 30, colour, alpha);
    std::vector<float> layer(4 * kW * kH);
    sums.resolve(layer.data());
    return layer;
  };
  std::uint64_t groupedFragments = 0, oneFragments = 0;
  const std::vector<float> grouped = layerOf(true, groupedFragments);
  const std::vector<float> one = layerOf(false, oneFragments);
  EXPECT_EQ(groupedFragments, oneFragments);
  EXPECT_LT(oneFragments, 20u);  // the rows from x < 0 on are off the frame
  EXPECT_EQ(grouped, one);
}

// A line half a pixel wide from (x, first) over rows [first, end), moving dx columns over them,
// at depth 0.5.
Line lineOver(float x, float dx, int first, int end) {
  Line l{};
  l.xt = x, l.yt = static_cast<float>(first), l.zt = 0.5f, l.dx = dx, l.dz = 0;
  l.invDy = 1.0f / static_cast<float>(end - first), l.coverage = 0.5f;
  l.first = first, l.end = end;
  return l;
}

// The runs are listed per strip of columns and added strip by strip (StreakSums.h): straight
// lines in the columns either side of strip edges, one running on to the last row, and a line
// slanted across an edge, against each pixel's value worked out by hand - T = exp(-sum b) of the
// lines over it, L = their colour times 1 - T - and (0, 0, 0, 1) everywhere else.
TEST(StreakSums, RunsEitherSideOfAStripEdgeLandInTheirOwnPixels) {
  constexpr int kW = 100, kH = 30;
  const std::vector<float> depth(kW * kH, 1.0f);
  const Vec3 colour(0.8f, 0.6f, 0.4f);
  const float alpha = 0.25f;
  StreakSums sums;
  sums.begin(kW, kH, depth.data(), 2);
  // Columns 31 | 32 and 63 | 64; the last one from row 20 to the top.
  std::uint64_t fragments = sums.add(0, lineOver(31.5f, 0, 2, 12), 2, 12, colour, alpha);
  fragments += sums.add(1, lineOver(32.5f, 0, 5, 15), 5, 15, colour, alpha);
  fragments += sums.add(0, lineOver(63.5f, 0, 0, 10), 0, 10, colour, alpha);
  fragments += sums.add(1, lineOver(64.5f, 0, 20, kH), 20, kH, colour, alpha);
  // From column 62 to column 65 over rows 10..22: across the edge at 64.
  fragments += sums.add(0, lineOver(62.2f, 3, 10, 22), 10, 22, colour, alpha);
  std::vector<float> layer(4 * kW * kH);
  sums.resolve(layer.data());
  EXPECT_EQ(fragments, 10u + 10u + 10u + 10u + 12u);
  EXPECT_EQ(sums.runs(), 4u + 4u);    // the slanted line: one run in each of its 4 columns
  std::vector<int> over(kW * kH, 0);  // lines over each pixel
  auto cover = [&](int x, int first, int end) {
    for (int y = first; y < end; ++y) ++over[static_cast<std::size_t>(y) * kW + x];
  };
  cover(31, 2, 12), cover(32, 5, 15), cover(63, 0, 10), cover(64, 20, kH);
  for (int y = 10; y < 22; ++y) {  // the slanted line's column in row y, as add() takes it
    const float s = (static_cast<float>(y) + 0.5f - 10) / 12;
    cover(static_cast<int>(62.2f + 3 * s), y, y + 1);
  }
  const float b = -std::log(1 - alpha);
  for (std::size_t p = 0; p < over.size(); ++p) {
    const float t = std::exp(-b * static_cast<float>(over[p]));
    EXPECT_NEAR(layer[4 * p + 3], t, 2e-4f) << p;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(layer[4 * p + k], colour[k] * (1 - t), 2e-4f) << p;
  }
}

// The resolve's exp (render/rain/ExpNear.h) at every x = -w 2^-18 the sums give for w up to
// 2^23 (T down to exp(-32)) in steps of 7, and past the clamp: within 2 ulp of std::exp, exp(0) = 1
// exactly, and the lanes the same bits as one at a time.
TEST(StreakSums, TheResolvesExpIsWithinTwoUlpAndTheLanesGiveTheSameBits) {
  std::vector<float> xs;
  for (std::int32_t w = 0; w < (1 << 23); w += 7) xs.push_back(static_cast<float>(w) * -0x1p-18f);
  for (float x : {-80.0f, -86.9f, -87.0f, -90.0f, -500.0f}) xs.push_back(x);
  while (xs.size() % 16 != 0) xs.push_back(0);
  EXPECT_EQ(expNear(0.0f), 1.0f);
  float worst = 0;
  for (float x : xs) {
    const float e = expNear(x), exact = std::exp(std::max(x, -87.0f));
    worst = std::max(worst, std::abs(e - exact) / (std::nextafter(exact, 2.0f) - exact));
  }
  EXPECT_LE(worst, 2.0f);
  EXPECT_LT(expNear(-500.0f), 2e-38f);
#if defined(__AVX512F__)
  for (std::size_t i = 0; i < xs.size(); i += 16) {
    alignas(64) float lanes[16];
    _mm512_store_ps(lanes, expNear(_mm512_loadu_ps(xs.data() + i)));
    for (int k = 0; k < 16; ++k) ASSERT_EQ(lanes[k], expNear(xs[i + k])) << xs[i + k];
  }
#endif
}

// A frame 40 columns wide: a strip of 32 and one of 8 (the lanes' masked tail). Column x gets
// lines(x) lines over rows [x % 32, 40): every pixel against its T = (1 - a)^lines and L = c (1 -
// T), and columns 3 and 35 - the same lines, in the full strip and in the tail - the same bits.
TEST(StreakSums, TheResolveWritesEachPixelsSumsInFullAndPartStrips) {
  constexpr int kW = 40, kH = 40;
  const auto lines = [](int x) { return x < 32 ? x + 1 : x - 31; };  // column 35 as column 3
  const std::vector<float> depth(kW * kH, 1.0f);
  std::vector<float> layer(4 * kW * kH, -1.0f);
  {
    StreakSums sums;
    sums.begin(kW, kH, depth.data(), 1);
    for (int x = 0; x < kW; ++x)
      for (int k = 0; k < lines(x); ++k)
        sums.add(0, lineOver(static_cast<float>(x) + 0.5f, 0, x % 32, kH), x % 32, kH,
                 Vec3(0.8f, 0.6f, 0.4f), 0.125f);
    sums.resolve(layer.data());
  }
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float* q = layer.data() + 4 * (static_cast<std::size_t>(y) * kW + x);
      const int over = y >= x % 32 ? lines(x) : 0;
      const float t = std::pow(1 - 0.125f, static_cast<float>(over));
      const float bound = 2e-4f * static_cast<float>(over);
      EXPECT_NEAR(q[3], t, bound) << x << " " << y;
      EXPECT_NEAR(q[0], 0.8f * (1 - t), bound) << x << " " << y;
      EXPECT_NEAR(q[1], 0.6f * (1 - t), bound) << x << " " << y;
      EXPECT_NEAR(q[2], 0.4f * (1 - t), bound) << x << " " << y;
      if (over == 0) {
        EXPECT_EQ(std::vector<float>(q, q + 4), (std::vector<float>{0, 0, 0, 1}));
      }
    }
  for (int y = 0; y < kH; ++y)
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(layer[4 * (static_cast<std::size_t>(y) * kW + 3) + k],
                layer[4 * (static_cast<std::size_t>(y) * kW + 35) + k])
          << y;
}

// The CPU composite (render/rain/ComposeOver.h) over 1,027 pixels (the lanes take 4 at a time, the
// last 3 one at a time): each channel within rounding of 255 L + T c (exactly at most a few in a
// thousand off by one, at a half), clamped, the alpha kept, pixels no streak covers unchanged, and
// the tail's pixels - copies of the first three - the same bytes as the lanes gave them.
TEST(ComposeOver, EachChannelIsTheLayerOverTheFrameRoundedAndTheAlphaKept) {
  constexpr int kPixels = 1027;
  std::vector<float> layer(4 * kPixels);
  std::vector<std::uint8_t> rgba(4 * kPixels);
  std::uint32_t state = 12345;
  const auto next = [&state]() { return state = state * 1664525u + 1013904223u, state >> 8; };
  for (int p = 0; p < kPixels; ++p) {
    const float t = static_cast<float>(next() % 1001) / 1000.0f;
    for (int k = 0; k < 3; ++k)
      layer[4 * p + k] = (1 - t) * static_cast<float>(next() % 1001) / 1000.0f;
    layer[4 * p + 3] = t;
    for (int k = 0; k < 4; ++k) rgba[4 * p + k] = static_cast<std::uint8_t>(next());
  }
  for (int p : {5, 6, 7})
    layer[4 * p] = layer[4 * p + 1] = layer[4 * p + 2] = 0, layer[4 * p + 3] = 1;
  layer[4 * 8] = 1.0f, layer[4 * 8 + 3] = 1.0f, rgba[4 * 8] = 255;  // over 255: clamped
  for (int k = 0; k < 12; ++k)  // the tail: copies of pixels 0, 1, 2
    layer[4 * (kPixels - 3) + k] = layer[k], rgba[4 * (kPixels - 3) + k] = rgba[k];
  const std::vector<std::uint8_t> before = rgba;
  composeOver(layer, rgba);
  int offByOne = 0;
  for (int p = 0; p < kPixels; ++p) {
    EXPECT_EQ(rgba[4 * p + 3], before[4 * p + 3]) << p;
    for (int k = 0; k < 3; ++k) {
      const double v = 255.0 * layer[4 * p + k] + double{layer[4 * p + 3]} * before[4 * p + k];
      const double expected = std::floor(std::clamp(v, 0.0, 255.0) + 0.5);
      EXPECT_NEAR(rgba[4 * p + k], expected, 1.0) << p << " " << k;
      offByOne += rgba[4 * p + k] != expected;
    }
  }
  EXPECT_LE(offByOne, 3 * kPixels / 100);
  for (int p : {5, 6, 7})
    for (int k = 0; k < 4; ++k) EXPECT_EQ(rgba[4 * p + k], before[4 * p + k]);
  EXPECT_EQ(rgba[4 * 8], 255);
  for (int k = 0; k < 12; ++k) EXPECT_EQ(rgba[4 * (kPixels - 3) + k], rgba[k]) << k;
}

// A list more than four times larger than its last frame's runs gives its memory back at the next
// frame: after a frame of 20,000 runs in one strip, then frames of one run, the lists hold room
// for a few runs, not 20,000 (review of 2026-11-27: memory was every list's peak).
TEST(StreakSums, AListFarLargerThanItsLastFramesRunsGivesItsMemoryBack) {
  constexpr int kW = 64, kH = 8;
  const std::vector<float> depth(kW * kH, 1.0f);
  const Vec3 colour(0.8f, 0.6f, 0.4f);
  std::vector<float> layer(4 * kW * kH);
  StreakSums sums;
  auto frame = [&](int lines) {
    sums.begin(kW, kH, depth.data(), 1);
    for (int i = 0; i < lines; ++i) sums.add(0, lineOver(5.5f, 0, 0, 1), 0, 1, colour, 0.01f);
    sums.resolve(layer.data());
    EXPECT_EQ(sums.runs(), static_cast<std::size_t>(lines));
  };
  frame(20000);
  EXPECT_GE(sums.runCapacity(), 20000u);
  frame(20000);  // a steady frame keeps its room: no allocation
  EXPECT_GE(sums.runCapacity(), 20000u);
  frame(1), frame(1);
  EXPECT_LT(sums.runCapacity(), 4096u);
  EXPECT_NEAR(layer[4 * (0 * kW + 5) + 3], 0.99f, 1e-3f);  // the one line still drawn
}

}  // namespace
}  // namespace sph::render::rain
