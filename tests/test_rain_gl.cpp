// render/rain on llvmpipe: the streak images (CPU), and frames with rain drawn by the real
// shaders through the splat renderer's layer hook - streak pixels where the drops are and none
// where they are not, none at all without drops, streaks along the projected velocity, and the
// spotlight's colour on the drops inside its cone only - for both rain.draw paths ("cpu" and
// "triangles"; tests/test_rain_raster_gl.cpp compares the two).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "render/gl/GlContext.h"
#include "render/rain/RainRenderer.h"
#include "render/rain/StreakImages.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/rain/RainSystem.h"
#include "sim/rain/Spotlight.h"
#include "sim/scene/Camera.h"

namespace sph::render::rain {
namespace {

constexpr int kWidth = 96, kHeight = 64;

TEST(StreakImages, LayersDifferAndHaveABrightCoreFadingToTheEdges) {
  const StreakImages s = generateStreakImages(8, 16, 64, 1);
  ASSERT_EQ(s.alpha.size(), 8u * 16 * 64);
  int differ = 0;
  for (int l = 0; l < 8; ++l) {
    EXPECT_GT(s.at(l, 32, 7), 100) << l;            // core
    EXPECT_LT(s.at(l, 32, 0), s.at(l, 32, 7) / 2);  // edge across
    EXPECT_LT(s.at(l, 0, 7), s.at(l, 32, 7));       // faded end
    if (l > 0 && s.at(l, 20, 7) != s.at(0, 20, 7)) ++differ;
  }
  EXPECT_GE(differ, 6);
  EXPECT_EQ(generateStreakImages(8, 16, 64, 1).alpha, s.alpha);
}

class GlFrame : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

// The rain tests, once per rain.draw.
class RainGl : public ::testing::TestWithParam<scene::RainDraw> {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};
INSTANTIATE_TEST_SUITE_P(Draw, RainGl,
                         ::testing::Values(scene::RainDraw::Cpu, scene::RainDraw::Triangles),
                         [](const auto& p) { return std::string(nameOf(p.param)); });

scene::CameraDesc camera() {
  scene::CameraDesc c;
  c.position = Vec3(0, 1, 4), c.target = Vec3(0, 1, 0);
  c.fovYDegrees = 45;
  return c;
}

scene::RainDesc desc(std::size_t count, scene::RainDraw draw) {
  scene::RainDesc d;
  d.draw = draw;
  d.count = count;
  d.near = 1, d.far = 4;
  d.dropWidth = 0.03f;
  d.exposure = 0.05f;
  return d;
}

// Pixel of a world point (row 0 at the top), or (-1, -1) behind the camera.
std::pair<int, int> pixelOf(const Vec3& p) {
  const scene::Mat4 m = cameraFrame(camera(), static_cast<float>(kWidth) / kHeight).projView;
  Eigen::Vector4f c(0, 0, 0, 0);
  for (int r = 0; r < 4; ++r) c[r] = m(r, 0) * p.x() + m(r, 1) * p.y() + m(r, 2) * p.z() + m(r, 3);
  if (c.w() <= 0) return {-1, -1};
  const float x = (c.x() / c.w() * 0.5f + 0.5f) * kWidth;
  const float y = (1 - (c.y() / c.w() * 0.5f + 0.5f)) * kHeight;
  return {static_cast<int>(x), static_cast<int>(y)};
}

frame::RenderImage frame(RainRenderer* layer) {
  splat::SplatRenderer r(kWidth, kHeight);
  if (layer) r.setLayers({layer});
  return r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera(), frame::Lighting{});
}

int difference(const frame::RenderImage& a, const frame::RenderImage& b, std::size_t pixel) {
  int d = 0;
  for (int k = 0; k < 3; ++k) d += std::abs(int(a.rgb[3 * pixel + k]) - int(b.rgb[3 * pixel + k]));
  return d;
}

TEST_P(RainGl, StreakPixelsAreWhereTheDropsAreAndNoneWithoutDrops) {
  const frame::RenderImage empty = frame(nullptr);
  sph::rain::RainSystem none(desc(0, GetParam()), static_cast<float>(kWidth) / kHeight);
  none.reset(camera());
  RainRenderer noDrops(desc(0, GetParam()));
  noDrops.setDrops(none);
  EXPECT_EQ(frame(&noDrops).rgb, empty.rgb);

  sph::rain::RainSystem drops(desc(200, GetParam()), static_cast<float>(kWidth) / kHeight);
  drops.reset(camera());
  RainRenderer layer(desc(200, GetParam()));
  layer.setDrops(drops);
  const frame::RenderImage rain = frame(&layer);
  // Near each drop (its streak runs 0.3 m up from it) the picture changed.
  std::vector<char> nearDrop(kWidth * kHeight, 0);
  int dropsSeen = 0, dropsOnScreen = 0;
  for (const Vec3& p : drops.positions()) {
    const auto [x, y] = pixelOf(p - 0.5f * drops.velocity() * 0.05f);  // streak middle
    if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) continue;
    ++dropsOnScreen;
    int changed = 0;
    for (int dy = -12; dy <= 12; ++dy)
      for (int dx = -4; dx <= 4; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= kWidth || yy >= kHeight) continue;
        nearDrop[static_cast<std::size_t>(yy * kWidth + xx)] = 1;
        changed += difference(rain, empty, static_cast<std::size_t>(yy * kWidth + xx)) > 6;
      }
    dropsSeen += changed > 0;
  }
  EXPECT_GT(dropsOnScreen, 180);  // every drop is in view; a streak's middle may be past the edge
  EXPECT_GT(dropsSeen, 0.9 * dropsOnScreen);
  // And nowhere else.
  int strays = 0, streakPixels = 0;
  for (std::size_t i = 0; i < nearDrop.size(); ++i) {
    const bool changed = difference(rain, empty, i) > 6;
    streakPixels += changed;
    strays += changed && !nearDrop[i];
  }
  std::printf("%d streak pixels, %d away from every drop\n", streakPixels, strays);
  EXPECT_GT(streakPixels, 200);
  EXPECT_EQ(strays, 0);
}

// One big drop falling in a side wind: the streak's principal axis in the picture is the
// projected velocity's direction.
TEST_P(RainGl, AStreakLiesAlongTheProjectedVelocity) {
  scene::RainDesc d = desc(1, GetParam());
  d.spawn = scene::RainSpawn::Region;
  d.region.lo = Vec3(-0.01f, 0.99f, 1.99f), d.region.hi = Vec3(0.01f, 1.01f, 2.01f);
  d.wind = Vec3(4, 0, 0);
  d.fallSpeed = 6;
  d.exposure = 0.1f;
  d.dropWidth = 0.02f;
  sph::rain::RainSystem one(d, static_cast<float>(kWidth) / kHeight);
  one.reset(camera());
  RainRenderer layer(d);
  layer.setDrops(one);
  const frame::RenderImage empty = frame(nullptr), rain = frame(&layer);
  double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const double w = difference(rain, empty, static_cast<std::size_t>(y * kWidth + x));
      sw += w, sx += w * x, sy += w * y, sxx += w * x * x, syy += w * y * y, sxy += w * x * y;
    }
  ASSERT_GT(sw, 0);
  const double mx = sx / sw, my = sy / sw;
  const double cxx = sxx / sw - mx * mx, cyy = syy / sw - my * my, cxy = sxy / sw - mx * my;
  const double axis = 0.5 * std::atan2(2 * cxy, cxx - cyy);  // principal axis angle
  const Vec3 head = one.positions()[0], tail = head - one.velocity() * d.exposure;
  const auto [hx, hy] = pixelOf(head);
  const auto [tx, ty] = pixelOf(tail);
  const double expected = std::atan2(double(hy - ty), double(hx - tx));
  double diff = std::fmod(std::abs(axis - expected), M_PI);
  diff = std::min(diff, M_PI - diff);
  std::printf("streak axis %.1f deg, projected velocity %.1f deg\n", axis * 180 / M_PI,
              expected * 180 / M_PI);
  EXPECT_LT(diff, 5 * M_PI / 180);
}

// A red spotlight whose cone holds the left half of the rain: drops in it are red, the others
// grey (the unlit tint), as eq. (13).
TEST_P(RainGl, DropsInTheConeTakeTheLightsColourTheOthersDoNot) {
  scene::RainDesc d = desc(200, GetParam());
  d.dropWidth = 0.015f;
  // The exact streaks, whose centre pixel takes the streak image's core: the default sums draw
  // these 4-10 pixel wide streaks with the image's mean along them, fainter at the centre, and
  // only ~40% of the lit drops' centre pixels pass the red test below (docs/rain.md, "The
  // default": near, wide streaks are where the sums lose).
  d.lodWidth = 0;
  scene::SpotlightDesc l;
  l.position = Vec3(-1.5f, 4, 2);
  l.direction = -Vec3::UnitY();
  l.height = 5;
  l.baseRadius = 3;
  l.colour = Vec3(1, 0, 0);
  l.intensity = 1;
  d.spotlight = l;
  sph::rain::RainSystem drops(d, static_cast<float>(kWidth) / kHeight);
  drops.reset(camera());
  RainRenderer layer(d);
  layer.setDrops(drops);
  const frame::RenderImage empty = frame(nullptr), rain = frame(&layer);
  int redLit = 0, lit = 0, redUnlit = 0, unlit = 0;
  for (const Vec3& p : drops.positions()) {
    const auto [x, y] = pixelOf(p - 0.5f * drops.velocity() * d.exposure);
    if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) continue;
    const std::size_t i = static_cast<std::size_t>(y * kWidth + x);
    if (difference(rain, empty, i) < 12) continue;  // hidden by a nearer streak's edge or faint
    const bool red = rain.rgb[3 * i] > rain.rgb[3 * i + 1] + 40;
    if (sph::rain::spotlightWeight(l, p) == 1) {
      ++lit, redLit += red;
    } else {
      ++unlit, redUnlit += red;
    }
  }
  std::printf("lit drops %d (%d red), unlit %d (%d red)\n", lit, redLit, unlit, redUnlit);
  EXPECT_GT(lit, 10);
  EXPECT_GT(unlit, 20);
  // Not all: a lit drop's pixel may be covered by an unlit streak in front of it.
  EXPECT_GT(redLit, 0.6 * lit);
  EXPECT_LT(redUnlit, 0.1 * unlit);
}

// The same spotlight lights the solids and the water (shaders/extra_lights.glsl): seen from above,
// a grey floor and a water splat turn red inside the cone's footprint and stay as they were
// outside it.
TEST_F(GlFrame, TheSpotlightLightsSolidsAndWaterInsideItsConeOnly) {
  scene::CameraDesc top;
  top.position = Vec3(0, 2, 0), top.target = Vec3::Zero(), top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 60;
  scene::BoundaryShape floor;
  floor.kind = scene::BoundaryShape::Kind::Block;
  floor.lo = Vec3(-2, -0.1f, -2), floor.hi = Vec3(2, 0, 2);
  solids::SolidRenderer solid({floor}, Aabb{Vec3(-3, -3, -3), Vec3(3, 3, 3)}, 0.01f);
  splat::SplatFrame water;
  water.halfSize = 0.15f;
  water.points.push_back(splat::SplatVertex{{0.5f, 0.05f, 0}, {0, 1, 0}});  // right of centre
  scene::SpotlightDesc l;
  l.position = Vec3(0.5f, 1, 0), l.direction = -Vec3::UnitY();
  l.height = 2, l.baseRadius = 0.6f;  // footprint radius 0.3 m on the floor around x = 0.5
  l.colour = Vec3(1, 0, 0), l.intensity = 1;
  frame::Lighting plain, spot;
  spot.spotlight = l;
  splat::SplatRenderer r(kWidth, kHeight);
  r.setLayers({&solid});
  const frame::RenderImage a = r.render(water, splat::SplatKind::Point, top, plain);
  const frame::RenderImage b = r.render(water, splat::SplatKind::Point, top, spot);
  // Pixels of world points on the floor seen from above: x right, z down the picture.
  auto pixel = [&](float x, float z) {
    const scene::Mat4 m = cameraFrame(top, static_cast<float>(kWidth) / kHeight).projView;
    Eigen::Vector4f c;
    for (int row = 0; row < 4; ++row) c[row] = m(row, 0) * x + m(row, 2) * z + m(row, 3);
    const int px = static_cast<int>((c.x() / c.w() * 0.5f + 0.5f) * kWidth);
    const int py = static_cast<int>((1 - (c.y() / c.w() * 0.5f + 0.5f)) * kHeight);
    return static_cast<std::size_t>(py * kWidth + px);
  };
  const std::size_t onWater = pixel(0.5f, 0), onLitFloor = pixel(0.5f, 0.22f),
                    onDarkFloor = pixel(-0.5f, 0);
  EXPECT_GT(int(b.rgb[3 * onWater]), int(a.rgb[3 * onWater]) + 30) << "water lit red";
  EXPECT_GT(int(b.rgb[3 * onLitFloor]), int(a.rgb[3 * onLitFloor]) + 15) << "floor lit red";
  EXPECT_EQ(b.rgb[3 * onLitFloor + 1], a.rgb[3 * onLitFloor + 1]) << "no green added";
  for (int k = 0; k < 3; ++k) EXPECT_EQ(b.rgb[3 * onDarkFloor + k], a.rgb[3 * onDarkFloor + k]);
}

}  // namespace
}  // namespace sph::render::rain
