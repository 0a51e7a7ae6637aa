// cdt-cpu, the reference of the CDT algorithm (seeds 000/001, section 3), without a GL context:
// the constants it shares with the GLSL, the collision camera of section 3.4 (eq. 1), the texel
// addressing, the empty first texture, the paper's response on a two-particle set-up, our
// separation response, and the texture's depth test and peeling.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "sim/cdt/CdtCamera.h"
#include "sim/cdt/CdtConstants.h"
#include "sim/cdt/CdtCpu.h"
#include "tests/CdtTestScenes.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

// ---- constants shared with shaders/cdt_constants.glsl ------------------------------------------

std::string sourceText(const std::string& relative) {
  std::ifstream in(test::sourcePath(relative));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every "const TYPE NAME = VALUE;" line of the GLSL constants file (ints, uints, floats, hex).
std::map<std::string, double> glslConstants() {
  std::map<std::string, double> values;
  std::istringstream in(sourceText("shaders/cdt_constants.glsl"));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string keyword, type, name, equals, value;
    if (!(words >> keyword >> type >> name >> equals >> value) || keyword != "const" ||
        equals != "=")
      continue;
    while (!value.empty() && (value.back() == ';' || value.back() == 'u')) value.pop_back();
    values[name] = value.rfind("0x", 0) == 0 ? static_cast<double>(std::stoull(value, nullptr, 16))
                                             : std::stod(value);
  }
  return values;
}

TEST(CdtConstants, GlslAndCppAgree) {
  const std::map<std::string, double> expected = {
      {"CDT_MAX_LAYERS", cdt::kMaxLayers},
      {"CDT_MAX_TEXEL_RANGE", cdt::kMaxTexelRange},
      {"CDT_EMPTY_TEXEL", cdt::kEmptyTexel},
      {"CDT_MAX_ID", cdt::kMaxId},
      {"CDT_NO_PARTNER", cdt::kNoPartner},
      {"CDT_OFFSCREEN", cdt::kOffscreen},
      {"CDT_FLAG_INTEGRATE", cdt::kFlagIntegrate},
      {"CDT_FLAG_TEXEL_POSITION", cdt::kFlagTexelPosition},
      {"CDT_FLAG_ADAPTIVE_RANGE", cdt::kFlagAdaptiveRange},
      {"CDT_FLAG_PAPER_RESPONSE", cdt::kFlagPaperResponse},
      {"CDT_FLAG_TEXTURE_VALID", cdt::kFlagTextureValid},
      {"CDT_ATTRIB_POSITION_TIME", cdt::kAttribPositionTime},
      {"CDT_ATTRIB_VELOCITY", cdt::kAttribVelocity},
      {"CDT_ATTRIB_ID", cdt::kAttribId},
      {"CDT_ATTRIB_ACCELERATION", cdt::kAttribAcceleration},
      {"CDT_PARAMS_BINDING", cdt::kParamsBinding},
      {"CDT_LAYER_UNIT", cdt::kLayerUnit},
      {"CDT_PEEL_DEPTH_UNIT", cdt::kPeelDepthUnit},
      {"CDT_PEEL_INDEX_UNIT", cdt::kPeelIndexUnit},
      {"CDT_IMAGE_COLOUR", cdt::kImageColour},
      {"CDT_IMAGE_DEPTH_KEY", cdt::kImageDepthKey},
      {"CDT_IMAGE_INDEX_KEY", cdt::kImageIndexKey},
      {"CDT_IMAGE_PREVIOUS_DEPTH", cdt::kImagePreviousDepth},
      {"CDT_IMAGE_PREVIOUS_INDEX", cdt::kImagePreviousIndex},
      {"CDT_PARTICLE_BINDING", cdt::kParticleBinding},
      {"CDT_WRITE_KEY_BINDING", cdt::kWriteKeyBinding},
      {"CDT_WRITE_GROUP_SIZE", cdt::kWriteGroupSize},
  };
  const std::map<std::string, double> glsl = glslConstants();
  for (const auto& [name, value] : expected) {
    const auto it = glsl.find(name);
    ASSERT_NE(it, glsl.end()) << name << " is not defined in shaders/cdt_constants.glsl";
    EXPECT_EQ(it->second, value)
        << name << " differs between sim/cdt/CdtConstants.h and shaders/cdt_constants.glsl";
  }
  for (const auto& [name, value] : glsl) {
    EXPECT_TRUE(expected.count(name)) << name << " (GLSL) has no C++ counterpart checked here";
  }
}

// The transform feedback buffer numbers are literals in the shader (layout qualifiers).
TEST(CdtConstants, TransformFeedbackBuffersAgree) {
  std::istringstream in(sourceText("shaders/cdt_collide.vert"));
  std::map<std::string, int> bufferOf;  // output name -> its xfb_buffer literal
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t at = line.find("xfb_buffer = ");
    const std::size_t semicolon = line.rfind(';');
    if (at == std::string::npos || semicolon == std::string::npos) continue;
    const std::size_t nameStart = line.find_last_of(' ', semicolon) + 1;
    bufferOf[line.substr(nameStart, semicolon - nameStart)] = std::stoi(line.substr(at + 13));
  }
  EXPECT_EQ(bufferOf["v_PositionTime"], cdt::kXfbState);
  EXPECT_EQ(bufferOf["v_Id"], cdt::kXfbState);
  EXPECT_EQ(bufferOf["v_Diag"], cdt::kXfbDiagnostics);
  EXPECT_EQ(bufferOf["v_WriteKey"], cdt::kXfbWriteKeys);
}

// ---- the collision camera (seed 000, section 3.4) ---------------------------------------------

scene::CameraDesc frontCamera() {
  scene::CameraDesc c;
  c.position = Vec3(0.1f, 0.2f, 2.0f);
  c.target = Vec3(0.1f, 0.2f, 0.0f);  // looking down world -z
  c.fovYDegrees = 40;
  c.near = 0.1f;
  c.far = 20;
  return c;
}

TEST(CdtCamera, RenderModeIsTheSceneCamera) {
  scene::CollisionDesc d;
  d.camera = scene::CdtCameraMode::Render;
  const scene::CameraDesc c = cdt::collisionCamera(d, frontCamera());
  EXPECT_EQ(c.position, frontCamera().position);
  EXPECT_EQ(c.target, frontCamera().target);
  EXPECT_THROW(cdt::collisionCamera(d, std::nullopt), std::invalid_argument);
}

TEST(CdtCamera, FixedModeUsesItsOwnPose) {
  scene::CollisionDesc d;
  d.camera = scene::CdtCameraMode::Fixed;
  d.pose = frontCamera();
  d.pose.position = Vec3(3, 1, 0);
  d.hasPose = true;
  scene::CameraDesc render = frontCamera();
  render.position = Vec3(-5, 0, 0);
  EXPECT_EQ(cdt::collisionCamera(d, render).position, Vec3(3, 1, 0));
}

// Eq. 1: C_CDC = C_RC + [0, 0, offset]. With a camera looking down world -z, its own z axis is
// world z, so the offset camera sits exactly `offset` further along world +z and the projection
// is that of the moved camera.
TEST(CdtCamera, OffsetModeFollowsEquation1) {
  scene::CollisionDesc d;
  d.camera = scene::CdtCameraMode::Offset;
  d.offset = 0.75f;
  const scene::CameraDesc moved = cdt::collisionCamera(d, frontCamera());
  EXPECT_NEAR((moved.position - (frontCamera().position + Vec3(0, 0, 0.75f))).norm(), 0.0f, 1e-6f);
  EXPECT_NEAR((moved.target - (frontCamera().target + Vec3(0, 0, 0.75f))).norm(), 0.0f, 1e-6f);

  scene::CameraDesc byHand = frontCamera();
  byHand.position.z() += 0.75f, byHand.target.z() += 0.75f;
  const cdt::View a = cdt::makeView(moved, {500, 500}), b = cdt::makeView(byHand, {500, 500});
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(a.projView.m[i], b.projView.m[i], 1e-6f) << i;

  // The paper's purpose: a positive offset (a longer shot) brings neighbours' texels closer.
  const cdt::View base = cdt::makeView(frontCamera(), {500, 500});
  const cdt::TexelAddress p = cdt::texelOf(base, 0.1f, 0.2f, 0.0f),
                          q = cdt::texelOf(base, 0.2f, 0.2f, 0.0f);
  const cdt::TexelAddress po = cdt::texelOf(a, 0.1f, 0.2f, 0.0f),
                          qo = cdt::texelOf(a, 0.2f, 0.2f, 0.0f);
  EXPECT_LT(qo.x - po.x, q.x - p.x);
  // And for a camera not aligned with world z, the offset is along the camera's own z axis.
  scene::CameraDesc oblique = frontCamera();
  oblique.position = Vec3(2, 1, 2), oblique.target = Vec3(0, 0, 0);
  const scene::CameraDesc movedOblique = cdt::collisionCamera(d, oblique);
  EXPECT_NEAR((movedOblique.position - oblique.position).norm(), 0.75f, 1e-5f);
  EXPECT_NEAR(
      (movedOblique.position - oblique.position).normalized().dot(Vec3(2, 1, 2).normalized()), 1.0f,
      1e-5f);
}

TEST(CdtCamera, TexelAddressing) {
  const cdt::View v = cdt::makeView(frontCamera(), {500, 400});
  // Just right of and above the look-at point: the texel right of and above the centre (0.3
  // texels in), depth inside (0, 1).
  const cdt::TexelAddress c = cdt::texelOf(v, 0.102f, 0.202f, 0.0f);
  ASSERT_TRUE(c.onScreen);
  EXPECT_EQ(c.x, 250);
  EXPECT_EQ(c.y, 200);
  EXPECT_GT(c.depth, 0.0f);
  EXPECT_LT(c.depth, 1.0f);
  // Behind the camera, beyond the far plane or outside the frustum: not on the texture.
  EXPECT_FALSE(cdt::texelOf(v, 0.1f, 0.2f, 3.0f).onScreen);
  EXPECT_FALSE(cdt::texelOf(v, 0.1f, 0.2f, -30.0f).onScreen);
  EXPECT_FALSE(cdt::texelOf(v, 5.0f, 0.2f, 0.0f).onScreen);
  // Nearer is smaller depth; right and up are larger texel indices (GL window coordinates).
  EXPECT_LT(cdt::texelOf(v, 0.1f, 0.2f, 0.5f).depth, c.depth);
  EXPECT_GT(cdt::texelOf(v, 0.3f, 0.2f, 0.0f).x, c.x);
  EXPECT_GT(cdt::texelOf(v, 0.1f, 0.4f, 0.0f).y, c.y);
  // Against the formula in long double for random points (pseudo-code lines 2-4).
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  int agree = 0, total = 0;
  for (int k = 0; k < 10000; ++k) {
    const float p[3] = {0.1f + u(rng), 0.2f + u(rng), u(rng)};
    const cdt::TexelAddress t = cdt::texelOf(v, p[0], p[1], p[2]);
    long double clip[4] = {0, 0, 0, 0};
    for (int r = 0; r < 4; ++r) {
      for (int col = 0; col < 3; ++col)
        clip[r] += static_cast<long double>(v.projView(r, col)) * p[col];
      clip[r] += v.projView(r, 3);
    }
    const long double nx = clip[0] / clip[3], ny = clip[1] / clip[3];
    if (!t.onScreen) continue;
    ++total;
    agree += t.x == static_cast<int>(std::floor((nx + 1) / 2 * 500)) &&
             t.y == static_cast<int>(std::floor((ny + 1) / 2 * 400));
  }
  EXPECT_GT(total, 1000);
  EXPECT_EQ(agree, total);
  // The adaptive texel range is the collision range projected, rounded up, within [1, cap].
  const double texelsPerMetre = v.texelScale * c.inverseW;
  EXPECT_EQ(cdt::adaptiveTexelRange(v, c.inverseW, static_cast<float>(2.5 / texelsPerMetre), 8), 3);
  EXPECT_EQ(cdt::adaptiveTexelRange(v, c.inverseW, 1e-6f, 8), 1);
  EXPECT_EQ(cdt::adaptiveTexelRange(v, c.inverseW, 10.0f, 8), 8);
}

// ---- the texture: nearest per texel, ties to draw order, peeled layers --------------------------

TEST(CdtCpu, TextureKeepsNearestThenFirstAndPeelsLayers) {
  scene::CollisionDesc d = test::testCollision();
  d.layers = 3;
  // On the axis of a camera looking down -z, with an odd resolution: the axis is the centre of
  // texel (64, 64), whatever the rounding.
  d.resolution = {129, 129};
  d.pose.position = Vec3(0, 0, 3);
  d.pose.target = Vec3(0, 0, 0);
  cdt::CdtCpu cpu(cdt::makeSettings(d, std::nullopt));
  // Four particles in that texel at different depths, two of them at the same place (equal depth):
  // the earlier one wins.
  const std::vector<float> x(4, 0.0f), y(4, 0.0f), z = {0.1f, 0.3f, 0.3f, -0.1f};
  const std::vector<std::uint32_t> id = {10, 11, 12, 13};
  cpu.writeTexture(x.data(), y.data(), z.data(), id.data(), 4);
  for (std::size_t i = 0; i < 4; ++i) {
    const cdt::TexelAddress t = cdt::texelOf(cpu.settings().view, x[i], y[i], z[i]);
    ASSERT_TRUE(t.onScreen && t.x == 64 && t.y == 64) << i;
  }
  EXPECT_EQ(cpu.texture().at(0, 64, 64)[3], 11.0f);  // nearest, first of the two at z = 0.3
  EXPECT_EQ(cpu.texture().at(1, 64, 64)[3], 12.0f);  // the other one at z = 0.3
  EXPECT_EQ(cpu.texture().at(2, 64, 64)[3], 10.0f);  // then z = 0.1; z = -0.1 is in no layer
  EXPECT_EQ(cpu.texture().keys[64 * 129 + 64],
            cdt::texelKey(cdt::texelOf(cpu.settings().view, 0, 0, 0.3f).depth, 1));
  std::size_t occupied = 0;
  for (const auto& texel : cpu.texture().texels) occupied += texel[3] >= 0;
  EXPECT_EQ(occupied, 3u);
}

TEST(CdtCpu, FirstStepFindsAnEmptyTexture) {
  scene::CollisionDesc d = test::testCollision();
  cdt::CdtCpu cpu(cdt::makeSettings(d, std::nullopt));
  Particles p = test::randomParticles(5000, 0.3f, 2);
  for (float& t : p.collideTime) t = -1;
  cpu.step(p, 0.001f, true);
  for (const cdt::Diagnostics& diag : cpu.diagnostics()) ASSERT_EQ(diag.partner, cdt::kNoPartner);
  EXPECT_TRUE(cpu.textureValid());
  cpu.step(p, 0.001f, true);
  std::size_t collided = 0;
  for (const cdt::Diagnostics& diag : cpu.diagnostics())
    collided += diag.partner != cdt::kNoPartner;
  EXPECT_GT(collided, 100u);
  cpu.reset();
  cpu.step(p, 0.001f, true);
  for (const cdt::Diagnostics& diag : cpu.diagnostics()) ASSERT_EQ(diag.partner, cdt::kNoPartner);
}

// ---- the paper's response on two particles (seed 000, section 3.2, lines 8 and 20-30) ----------

struct TwoParticles {
  scene::CollisionDesc desc;
  Particles p;
};

// A and B 6 mm apart along x (range 10 mm), in adjacent texels of a camera looking down -z, both
// falling; C far away as a bystander.
TwoParticles twoParticles() {
  TwoParticles s;
  scene::CollisionDesc& d = s.desc;
  d.range = 0.01f;
  d.response = scene::CollisionResponse::Paper;
  d.positionSource = scene::CdtPositionSource::Texel;
  d.speedFactor = 0.2f;
  d.cooldown = 0.05f;
  d.resolution = {200, 200};
  d.camera = scene::CdtCameraMode::Fixed;
  d.hasPose = true;
  d.pose.position = Vec3(0, 0, 1);
  d.pose.target = Vec3(0, 0, 0);
  d.pose.fovYDegrees = 45;  // ~4 mm per texel at the origin
  d.pose.near = 0.1f;
  s.p.append(Vec3(0.0f, 0.0f, 0.0f), Vec3(0.0f, -2.0f, 0.0f), 1, 1);    // A
  s.p.append(Vec3(0.006f, 0.0f, 0.0f), Vec3(0.0f, -1.0f, 0.0f), 2, 1);  // B
  s.p.append(Vec3(0.2f, 0.1f, 0.0f), Vec3(0.0f, 0.0f, 0.0f), 3, 1);     // C
  for (std::size_t i = 0; i < 3; ++i) s.p.ax[i] = 0, s.p.ay[i] = -9.81f, s.p.az[i] = 0;
  return s;
}

TEST(CdtPaperResponse, ReproducesTheRulesOnTwoParticles) {
  TwoParticles s = twoParticles();
  cdt::CdtCpu cpu(cdt::makeSettings(s.desc, std::nullopt));
  Particles& p = s.p;
  const double dt = 0.001;
  // Step 1: empty texture, everyone integrates (lines 26-30) and the cooldown runs down.
  cpu.step(p, static_cast<float>(dt), true);
  EXPECT_FLOAT_EQ(p.vy[0], static_cast<float>(-2.0 - 9.81 * dt));
  EXPECT_FLOAT_EQ(p.y[0], static_cast<float>(p.vy[0] * dt));
  EXPECT_FLOAT_EQ(p.collideTime[0], static_cast<float>(-1.0 - dt));
  const cdt::TexelAddress ta = cdt::texelOf(cpu.settings().view, p.x[0], p.y[0], p.z[0]);
  const cdt::TexelAddress tb = cdt::texelOf(cpu.settings().view, p.x[1], p.y[1], p.z[1]);
  ASSERT_EQ(std::abs(ta.x - tb.x), 1) << "the set-up needs A and B in neighbouring texels";
  ASSERT_EQ(ta.y, tb.y);

  // Step 2: A and B see each other (B is in the texel next to A's base texel).
  const Vec3 a0 = p.position(0), b0 = p.position(1), va = p.velocity(0), vb = p.velocity(1),
             c0 = p.position(2);
  cpu.step(p, static_cast<float>(dt), true);
  EXPECT_EQ(cpu.diagnostics()[0].partner, 2u);
  EXPECT_EQ(cpu.diagnostics()[1].partner, 1u);
  EXPECT_EQ(cpu.diagnostics()[2].partner, cdt::kNoPartner);
  // Line 21: speed x 0.2; line 22: direction from the partner to itself; line 24 (times the step):
  // moved from where it started; line 23: cooldown.
  const Vec3 dirA = (a0 - b0).normalized();
  const Vec3 expectedVa = dirA * (0.2f * va.norm());
  EXPECT_NEAR((p.velocity(0) - expectedVa).norm(), 0.0f, 1e-6f);
  EXPECT_NEAR((p.position(0) - (a0 + expectedVa * static_cast<float>(dt))).norm(), 0.0f, 1e-7f);
  EXPECT_FLOAT_EQ(p.collideTime[0], 0.05f);
  const Vec3 expectedVb = -dirA * (0.2f * vb.norm());
  EXPECT_NEAR((p.velocity(1) - expectedVb).norm(), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(p.collideTime[1], 0.05f);
  // C, alone, keeps falling.
  EXPECT_FLOAT_EQ(p.vy[2], static_cast<float>(-2 * 9.81 * dt));
  EXPECT_FLOAT_EQ(p.x[2], c0.x());

  // Step 3: still 6 mm apart, but cooling down (line 8): no collision, gravity again, the
  // cooldown runs down by the step.
  const Vec3 va2 = p.velocity(0);
  cpu.step(p, static_cast<float>(dt), true);
  EXPECT_EQ(cpu.diagnostics()[0].partner, cdt::kNoPartner);
  EXPECT_EQ(cpu.diagnostics()[0].texelRange, 0u) << "a cooling particle must not search";
  EXPECT_NEAR(p.vy[0], va2.y() - 9.81f * static_cast<float>(dt), 1e-6f);
  EXPECT_FLOAT_EQ(p.collideTime[0], static_cast<float>(0.05 - dt));
}

TEST(CdtPaperResponse, OutOfRangeOrTheNearestOnly) {
  // Out of range: 12 mm apart with a 10 mm range, nothing happens.
  TwoParticles s = twoParticles();
  s.p.x[1] = 0.012f;
  s.desc.texelRange = 4;  // B is inside the window, only the range keeps it out
  cdt::CdtCpu cpu(cdt::makeSettings(s.desc, std::nullopt));
  cpu.step(s.p, 0.001f, true);
  cpu.step(s.p, 0.001f, true);
  EXPECT_EQ(cpu.diagnostics()[0].partner, cdt::kNoPartner);
  EXPECT_EQ(cpu.diagnostics()[0].texelRange, 4u);
  // Two partners in range: the nearer one wins (lines 16-19), whichever texel comes first.
  TwoParticles t = twoParticles();
  t.p.append(Vec3(-0.004f, 0.0f, 0.0f), Vec3(0, -2, 0), 4, 1);
  t.p.ax[3] = 0, t.p.ay[3] = -9.81f, t.p.az[3] = 0;
  t.desc.positionSource = scene::CdtPositionSource::Particle;
  cdt::CdtCpu cpu2(cdt::makeSettings(t.desc, std::nullopt));
  cpu2.step(t.p, 0.001f, true);
  cpu2.step(t.p, 0.001f, true);
  EXPECT_EQ(cpu2.diagnostics()[0].partner, 4u);
  EXPECT_EQ(cpu2.diagnostics()[0].candidates, 2u);
}

// Our default response: apart to the range, no velocity towards each other.
TEST(CdtSeparateResponse, PushesApartAndStopsTheApproach) {
  TwoParticles s = twoParticles();
  s.desc.response = scene::CollisionResponse::Separate;
  s.desc.positionSource = scene::CdtPositionSource::Particle;
  s.desc.cooldown = 0;
  s.p.vx[0] = 0.5f, s.p.vx[1] = -0.5f;  // approaching along x
  s.p.vy[0] = s.p.vy[1] = 0;
  s.p.ay[0] = s.p.ay[1] = 0;
  cdt::CdtCpu cpu(cdt::makeSettings(s.desc, std::nullopt));
  cpu.step(s.p, 0.001f, true);  // empty texture: just moves, 5 mm apart now
  const float before = (s.p.position(0) - s.p.position(1)).norm();
  cpu.step(s.p, 0.0f, true);  // dt = 0: only the response acts
  const float after = (s.p.position(0) - s.p.position(1)).norm();
  EXPECT_NEAR(after, s.desc.range, 1e-6f) << "each moves half the overlap, together the whole";
  EXPECT_LT(before, after);
  EXPECT_NEAR(s.p.vx[0], 0.0f, 1e-7f);
  EXPECT_NEAR(s.p.vx[1], 0.0f, 1e-7f);
  EXPECT_LT(s.p.collideTime[0], 0.0f) << "no cooldown: it may collide again next step";
}

}  // namespace
}  // namespace sph
