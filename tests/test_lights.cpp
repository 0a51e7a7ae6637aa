// render/lights: particles as lights (seed 004) on the real GL (llvmpipe). One light in an empty
// volume gives the attenuation formula at voxel centres; the race-free accumulation equals a CPU
// sum of many lights, where the paper's unsynchronised read-modify-write loses light; the
// shading's filters (extra_lights.glsl) match a CPU evaluation of the same textures; a light over
// a plane lights the drawn plane as the formula says; the exact reference agrees with a
// hand-computed point and ranks trilinear above nearest; a volume GL cannot hold is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>

#include "render/gl/GlContext.h"
#include "render/lights/ExactLights.h"
#include "render/lights/LightVolume.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/scene/Camera.h"
#include "sim/InputError.h"
#include "sim/lights/LightParticles.h"
#include "tests/LightTestScenes.h"

namespace sph::render::lights {
namespace {

using Texels = std::vector<std::array<float, 4>>;

// 8^3 voxels of 0.25 m from (-1, -1, -1).
LightsDesc smallVolume() {
  LightsDesc d;
  d.origin = Vec3(-1, -1, -1);
  d.voxelSize = 0.25f;
  d.voxels = {8, 8, 8};
  d.attenuation = {1.0f, 0.5f, 2.0f};
  d.range = 0.6f;
  return d;
}

using test::light;

Vec3 voxelCentre(const LightsDesc& d, int x, int y, int z) {
  return d.origin + d.voxelSize * Vec3(x + 0.5f, y + 0.5f, z + 0.5f);
}

// The CPU sum the volume should hold: colour texture (rgb) and direction texture (xyz).
void cpuSums(const LightsDesc& d, const std::vector<LightParticle>& lights, Texels& colour,
             Texels& direction) {
  colour.assign(d.voxelCount(), {0, 0, 0, 0});
  direction.assign(d.voxelCount(), {0, 0, 0, 0});
  for (int z = 0; z < d.voxels[2]; ++z)
    for (int y = 0; y < d.voxels[1]; ++y)
      for (int x = 0; x < d.voxels[0]; ++x) {
        const std::size_t v = (static_cast<std::size_t>(z) * d.voxels[1] + y) * d.voxels[0] + x;
        const Vec3 c = voxelCentre(d, x, y, z);
        for (const LightParticle& l : lights) {
          const Vec3 p(l.position[0], l.position[1], l.position[2]);
          const float dist = (p - c).norm();
          const float att = lightAttenuation(d, dist);
          if (att == 0) continue;
          for (int a = 0; a < 3; ++a) {
            colour[v][static_cast<std::size_t>(a)] += att * l.colour[static_cast<std::size_t>(a)];
            if (dist > 0)
              direction[v][static_cast<std::size_t>(a)] += (p - c)[a] / dist * l.colour[3];
          }
        }
      }
}

class LightsGl : public ::testing::Test {
 protected:
  void SetUp() override { context_ = std::make_unique<gl::GlContext>(gl::GlContext::headless()); }
  std::unique_ptr<gl::GlContext> context_;
};

// Seed 004 eq. 1 with the text's parentheses, 1 / (c + l d + q d^2), at every voxel centre within
// range, zero beyond; the direction texture holds the unit vector to the light times intensity.
// Stored as RGBA16F (the paper's format): relative precision 2^-11, plus the fixed-point step.
TEST_F(LightsGl, OneLightGivesTheAttenuationFormulaAtVoxelCentres) {
  for (LightAccumulate mode : {LightAccumulate::Atomic, LightAccumulate::Paper}) {
    LightsDesc d = smallVolume();
    d.accumulate = mode;
    LightVolume volume(d);
    const Vec3 p(0.13f, -0.21f, 0.17f), colour(1.0f, 0.5f, 0.25f);
    volume.update({light(p, colour, 2.0f)});
    const Texels c = volume.readColour(), dir = volume.readDirection();
    int inRange = 0;
    for (int z = 0; z < 8; ++z)
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
          const std::size_t v = (static_cast<std::size_t>(z) * 8 + y) * 8 + x;
          const float dist = (p - voxelCentre(d, x, y, z)).norm();
          const float att = dist <= d.range ? 1.0f / (1.0f + 0.5f * dist + 2.0f * dist * dist) : 0;
          inRange += att > 0;
          for (std::size_t a = 0; a < 3; ++a) {
            const float expected = att * 2.0f * colour[static_cast<int>(a)];
            EXPECT_NEAR(c[v][a], expected, 1e-3f * expected + 1e-4f) << x << y << z;
            const float unit =
                att > 0 ? (p - voxelCentre(d, x, y, z))[static_cast<int>(a)] / dist * 2.0f : 0;
            EXPECT_NEAR(dir[v][a], unit, 1e-3f * std::abs(unit) + 1e-4f) << x << y << z;
          }
        }
    EXPECT_GT(inRange, 20) << "the light reaches a ball of voxels";
    // A voxel at 0.6 m is lit, at 0.85 m not: spot values.
    EXPECT_GT(c[(4 * 8 + 3) * 8 + 4][0], 0.5f);
  }
}

// Many lights in one small volume, many per voxel: the atomic sums equal the CPU sums up to the
// fixed-point rounding (half a step per light) and the RGBA16F storage; the paper's imageLoad /
// imageStore loses most of the light where invocations share voxels.
TEST_F(LightsGl, AtomicAccumulationEqualsTheCpuSumWherePaperLosesLight) {
  LightsDesc d = smallVolume();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.2f, 0.2f);
  std::vector<LightParticle> lights;
  for (int i = 0; i < 2048; ++i)
    lights.push_back(light(Vec3(u(rng), u(rng), u(rng)), Vec3(1.0f, 0.6f, 0.3f), 0.05f));
  Texels cpuColour, cpuDirection;
  cpuSums(d, lights, cpuColour, cpuDirection);
  double cpuTotal = 0, atomicTotal = 0, paperTotal = 0;
  {
    LightVolume volume(d);
    volume.update(lights);
    const Texels c = volume.readColour(), dir = volume.readDirection();
    const float rounding = 2048 * 0.5f * 0.05f / kFixedSteps;  // half a step per light
    for (std::size_t v = 0; v < c.size(); ++v)
      for (std::size_t a = 0; a < 3; ++a) {
        EXPECT_NEAR(c[v][a], cpuColour[v][a], 2e-3f * cpuColour[v][a] + rounding);
        EXPECT_NEAR(dir[v][a], cpuDirection[v][a], 2e-3f * std::abs(cpuDirection[v][a]) + rounding);
        cpuTotal += cpuColour[v][a], atomicTotal += c[v][a];
      }
  }
  d.accumulate = LightAccumulate::Paper;
  LightVolume paper(d);
  paper.update(lights);
  for (const auto& t : paper.readColour()) paperTotal += t[0] + t[1] + t[2];
  EXPECT_NEAR(atomicTotal / cpuTotal, 1.0, 1e-3);
  EXPECT_LT(paperTotal / cpuTotal, 0.9)
      << "the paper's race loses updates: " << paperTotal / cpuTotal;
}

// --- The shading's filters against a CPU evaluation of the same (read-back) textures ---

struct CpuVolume {
  LightsDesc d;
  Texels colour, direction;
  std::array<float, 4> texel(const Texels& t, int x, int y, int z) const {
    if (x < 0 || y < 0 || z < 0 || x >= d.voxels[0] || y >= d.voxels[1] || z >= d.voxels[2])
      return {0, 0, 0, 0};
    return t[(static_cast<std::size_t>(z) * d.voxels[1] + y) * d.voxels[0] + x];
  }
  static std::array<float, 4> weights(float f, float s) {
    const float f2 = f * f, f3 = f2 * f;
    return {s * (-f3 + 2 * f2 - f), (2 - s) * f3 + (s - 3) * f2 + 1,
            (s - 2) * f3 + (3 - 2 * s) * f2 + s * f, s * (f3 - f2)};
  }
  Vec3 filtered(const Texels& t, const Vec3& g) const {
    Vec3 sum = Vec3::Zero();
    auto add = [&](float w, int x, int y, int z) {
      const auto v = texel(t, x, y, z);
      sum += w * Vec3(v[0], v[1], v[2]);
    };
    if (d.filter == LightFilter::Nearest) {
      add(1, static_cast<int>(std::floor(g.x())), static_cast<int>(std::floor(g.y())),
          static_cast<int>(std::floor(g.z())));
      return sum;
    }
    const Vec3 c = g - Vec3::Constant(0.5f);
    const int ix = static_cast<int>(std::floor(c.x())), iy = static_cast<int>(std::floor(c.y())),
              iz = static_cast<int>(std::floor(c.z()));
    const Vec3 f = c - Vec3(ix, iy, iz);
    if (d.filter == LightFilter::Trilinear) {
      for (int k = 0; k < 8; ++k) {
        const int ox = k & 1, oy = (k >> 1) & 1, oz = k >> 2;
        add((ox ? f.x() : 1 - f.x()) * (oy ? f.y() : 1 - f.y()) * (oz ? f.z() : 1 - f.z()), ix + ox,
            iy + oy, iz + oz);
      }
      return sum;
    }
    const float s = 0.5f * (1 - d.tension);
    const auto wx = weights(f.x(), s), wy = weights(f.y(), s), wz = weights(f.z(), s);
    for (int z = 0; z < 4; ++z)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
          add(wx[static_cast<std::size_t>(x)] * wy[static_cast<std::size_t>(y)] *
                  wz[static_cast<std::size_t>(z)],
              ix + x - 1, iy + y - 1, iz + z - 1);
    return sum;
  }
  Vec3 sampled(const Texels& t, const Vec3& g) const {
    const int n = d.oversampling;
    if (n <= 1) return filtered(t, g);
    Vec3 sum = Vec3::Zero();
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          sum += filtered(t, g + (Vec3(x, y, z) + Vec3::Constant(0.5f)) / static_cast<float>(n) -
                                 Vec3::Constant(0.5f));
    return sum / static_cast<float>(n * n * n);
  }
  Vec3 shade(const ProbePoint& p, const Vec3& base) const {
    const Vec3 g = (p.position - d.origin) / d.voxelSize;
    const Vec3 c = sampled(colour, g).cwiseMax(0.0f);
    const Vec3 dir = sampled(direction, g);
    if (dir.norm() < 1e-6f) return Vec3::Zero();
    const Vec3 l = dir.normalized();
    const Vec3 r = 2 * p.normal.dot(l) * p.normal - l;
    return d.diffuse * std::max(p.normal.dot(l), 0.0f) * base.cwiseProduct(c) +
           d.specular * std::pow(std::max(r.dot(p.toEye), 0.0f), d.shininess) * c;
  }
};

std::vector<ProbePoint> probePoints(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.9f, 0.9f);
  std::vector<ProbePoint> points;
  for (int i = 0; i < count; ++i) {
    ProbePoint p;
    p.position = Vec3(u(rng), u(rng), u(rng));
    p.normal = Vec3(u(rng), u(rng) + 1.2f, u(rng)).normalized();
    p.toEye = Vec3(u(rng), 1.0f, u(rng)).normalized();
    points.push_back(p);
  }
  return points;
}

TEST_F(LightsGl, EveryFilterMatchesItsCpuEvaluation) {
  LightsDesc d = smallVolume();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.8f, 0.8f);
  std::vector<LightParticle> lights;
  for (int i = 0; i < 40; ++i)
    lights.push_back(light(Vec3(u(rng), u(rng), u(rng)), Vec3(1, 0.7f, 0.4f), 0.8f));
  LightVolume volume(d);
  volume.update(lights);
  CpuVolume cpu{d, volume.readColour(), volume.readDirection()};
  const std::vector<ProbePoint> points = probePoints(300, 11);
  const Vec3 base(0.8f, 0.7f, 0.6f);
  for (LightFilter f : {LightFilter::Nearest, LightFilter::Trilinear, LightFilter::Tricubic}) {
    for (int n : {1, 2}) {
      const float tension = f == LightFilter::Tricubic && n == 2 ? 1.0f : 0.0f;
      volume.setFilter(f, tension, n);
      cpu.d.filter = f, cpu.d.tension = tension, cpu.d.oversampling = n;
      const std::vector<Vec3> gpu = volume.probe(points, base);
      int lit = 0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3 want = cpu.shade(points[i], base);
        lit += want.maxCoeff() > 0.01f;
        // llvmpipe's linear filter weights are 8-bit fixed point: 1/256 of the texel values.
        const float tol =
            f == LightFilter::Trilinear ? 2e-2f * want.norm() + 4e-3f : 1e-4f + 1e-4f * want.norm();
        EXPECT_LT((gpu[i] - want).norm(), tol) << nameOf(f) << " x" << n << " point " << i;
      }
      EXPECT_GT(lit, 50) << nameOf(f);
    }
  }
}

// The exact reference at a point, by hand: one light 0.3 m above a point of an upward surface,
// seen from straight above: diffuse = kd base att, specular = ks att (r . v = 1).
TEST(ExactLights, OneLightOverAPointByHand) {
  LightsDesc d = smallVolume();
  d.attenuation = {1.0f, 0.0f, 4.0f};
  d.diffuse = 0.8f, d.specular = 0.5f, d.shininess = 8;
  const ExactLights exact(d, {light(Vec3(0.1f, 0.3f, 0.0f), Vec3(1.0f, 0.5f, 0.25f), 2.0f)});
  const LightTerms t =
      exact.at(Vec3(0.1f, 0, 0), Vec3::UnitY(), Vec3::UnitY(), Vec3(0.5f, 0.5f, 1));
  const float att = 1.0f / (1.0f + 4.0f * 0.09f);  // 0.7353
  EXPECT_NEAR(t.diffuse.x(), 0.8f * 0.5f * att * 2.0f, 1e-6f);
  EXPECT_NEAR(t.diffuse.z(), 0.8f * 1.0f * att * 0.5f, 1e-6f);
  EXPECT_NEAR(t.specular.y(), 0.5f * att * 1.0f, 1e-6f);
  // 45 degrees off (d = 0.3 sqrt 2 < range 0.6): n.l = cos 45; r = reflect(-l, n) is 45 degrees
  // the other side of n, so r.v = cos 45 too.
  const LightTerms side = exact.at(Vec3(-0.2f, 0, 0), Vec3::UnitY(), Vec3::UnitY(), Vec3::Ones());
  const float d45 = 0.3f * std::sqrt(2.0f), att45 = 1.0f / (1.0f + 4.0f * d45 * d45);
  EXPECT_NEAR(side.diffuse.x(), 0.8f * att45 * 2.0f * std::sqrt(0.5f), 1e-5f);
  EXPECT_NEAR(side.specular.x(), 0.5f * att45 * 2.0f * std::pow(std::sqrt(0.5f), 8.0f), 1e-6f);
  // Out of range: nothing.
  EXPECT_EQ(exact.at(Vec3(0.9f, 0, 0), Vec3::UnitY(), Vec3::UnitY(), Vec3::Ones()).diffuse.norm(),
            0);
}

// Against the exact sum over many lights above a floor, trilinear beats nearest and tricubic is
// no worse than nearest (diffuse term, PSNR over 4096 floor points).
TEST_F(LightsGl, TrilinearBeatsNearestAgainstTheExactReference) {
  LightsDesc d = smallVolume();
  d.voxels = {16, 16, 16}, d.voxelSize = 0.125f;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.7f, 0.7f), height(0.08f, 0.7f);
  std::vector<LightParticle> lights;
  for (int i = 0; i < 200; ++i)
    lights.push_back(light(Vec3(u(rng), height(rng), u(rng)), Vec3(1, 0.8f, 0.5f), 0.02f));
  LightVolume volume(d);
  volume.update(lights);
  volume.terms = 1;
  const ExactLights exact(d, lights);
  std::vector<ProbePoint> points;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i)
      points.push_back({Vec3(-0.8f + 1.6f * (i + 0.5f) / 64, 0.03f, -0.8f + 1.6f * (j + 0.5f) / 64),
                        Vec3::UnitY(), Vec3(0.3f, 1.0f, 0.2f).normalized()});
  const Vec3 base(0.8f, 0.8f, 0.8f);
  std::vector<Vec3> want;
  for (const ProbePoint& p : points)
    want.push_back(exact.at(p.position, p.normal, p.toEye, base).diffuse);
  double psnr[3];
  for (LightFilter f : {LightFilter::Nearest, LightFilter::Trilinear, LightFilter::Tricubic}) {
    volume.setFilter(f, 0.0f, 1);
    const LightError e = lightError(volume.probe(points, base), want);
    psnr[static_cast<int>(f)] = e.psnr;
    EXPECT_GT(e.psnr, 12.0) << nameOf(f);
  }
  EXPECT_GT(psnr[1], psnr[0] + 1.0) << "trilinear " << psnr[1] << " dB, nearest " << psnr[0];
  EXPECT_GT(psnr[2], psnr[0]) << "tricubic " << psnr[2] << " dB, nearest " << psnr[0];
  std::printf(
      "diffuse PSNR against the exact sum: nearest %.2f, trilinear %.2f, tricubic %.2f dB\n",
      psnr[0], psnr[1], psnr[2]);
}

// The drawn picture: a plane seen from above, lit only by one particle light 0.3 m over a voxel
// centre (nearest filter): the pixel under the light is kd base att(0.3) (n.l = 1), the pixel
// under the neighbouring voxel centre 0.3 m aside kd base att(0.3 sqrt 2) cos 45.
TEST_F(LightsGl, ALightOverAPlaneLightsTheDrawnPlaneByTheFormula) {
  LightsDesc d;
  d.origin = Vec3(-0.5f, -0.05f, -0.5f), d.voxelSize = 0.1f, d.voxels = {10, 10, 10};
  d.attenuation = {1.0f, 0.0f, 4.0f}, d.range = 0.5f, d.filter = LightFilter::Nearest;
  d.specular = 0;
  LightVolume volume(d);
  const Vec3 lamp(0.05f, 0.3f, 0.05f);
  volume.update({light(lamp, Vec3::Ones(), 1.0f)});
  BoundaryShape plane;
  plane.kind = BoundaryShape::Kind::Plane;
  plane.point = Vec3::Zero(), plane.normal = Vec3::UnitY();
  solids::SolidRenderer solids({plane}, Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, 0.02f);
  solids.material.ambient = 0, solids.material.diffuse = 0, solids.material.specular = 0;
  solids.material.colour = Vec3(0.8f, 0.6f, 0.4f);
  const int size = 128;
  splat::SplatRenderer r(size, size);
  r.setLayers({&solids});
  CameraDesc top;
  top.position = Vec3(0.05f, 2, 0.05f), top.target = Vec3(0.05f, 0, 0.05f), top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 30;
  splat::Lighting lighting;
  lighting.extra = &volume;
  const splat::RenderImage picture =
      r.render(splat::SplatFrame{}, splat::SplatKind::Point, top, lighting);
  const CameraFrame cf = cameraFrame(top, 1.0f);
  auto pixel = [&](const Vec3& w) {
    float c[4];
    for (int row = 0; row < 4; ++row)
      c[row] = cf.projView(row, 0) * w.x() + cf.projView(row, 1) * w.y() +
               cf.projView(row, 2) * w.z() + cf.projView(row, 3);
    const int px = static_cast<int>((c[0] / c[3] + 1) * 0.5f * size);
    const int py = static_cast<int>((1 - c[1] / c[3]) * 0.5f * size);
    return static_cast<std::size_t>(py * size + px);
  };
  auto linear = [](std::uint8_t s8) {
    const float s = s8 / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
  };
  auto expectPixel = [&](const Vec3& w, float lightValue) {
    const std::size_t p = pixel(w);
    for (int a = 0; a < 3; ++a) {
      const float want = solids.material.colour[a] * lightValue;
      // One 8-bit sRGB step at that level, in linear terms.
      const float step =
          linear(static_cast<std::uint8_t>(std::min(255, picture.rgb[3 * p + a] + 1))) -
          linear(picture.rgb[3 * p + a]);
      EXPECT_NEAR(linear(picture.rgb[3 * p + a]), want, step + 2e-3f) << "channel " << a;
    }
  };
  expectPixel(Vec3(0.05f, 0, 0.05f), 1.0f / (1 + 4 * 0.09f));
  const float d45 = 0.3f * std::sqrt(2.0f);
  expectPixel(Vec3(0.35f, 0, 0.05f), std::sqrt(0.5f) / (1 + 4 * d45 * d45));
  expectPixel(Vec3(-0.45f, 0, -0.45f), 0.0f);  // out of range
}

// The water's splats take the same light as the solids. (Their programs without particle-light
// code are for scenes without `lights`; a lit scene must get the lit ones.)
TEST_F(LightsGl, WaterSplatsAreLitByTheVolumeToo) {
  LightsDesc d;
  d.origin = Vec3(-0.5f, -0.05f, -0.5f), d.voxelSize = 0.1f, d.voxels = {10, 10, 10};
  d.attenuation = {1.0f, 0.0f, 4.0f}, d.range = 0.5f, d.filter = LightFilter::Nearest;
  d.specular = 0;
  LightVolume volume(d);
  volume.update({light(Vec3(0.05f, 0.3f, 0.05f), Vec3::Ones(), 1.0f)});
  splat::SplatFrame frame;
  frame.halfSize = 0.05f;
  frame.points.push_back(splat::SplatVertex{{0.05f, 0, 0.05f}, {0, 1, 0}});  // facing the lamp
  const int size = 32;
  splat::SplatRenderer r(size, size);
  CameraDesc top;
  top.position = Vec3(0.05f, 2, 0.05f), top.target = Vec3(0.05f, 0, 0.05f), top.up = Vec3(0, 0, -1);
  top.fovYDegrees = 30;
  splat::Lighting unlit;  // no scene light at all: only the particle light can colour the splat
  unlit.ambient = 0, unlit.diffuse = 0, unlit.specular = 0, unlit.environment = false;
  unlit.base = Vec3(0.8f, 0.6f, 0.4f);
  splat::Lighting lit = unlit;
  lit.extra = &volume;
  const std::size_t centre = static_cast<std::size_t>(size / 2 * size + size / 2);
  const splat::RenderImage dark = r.render(frame, splat::SplatKind::Point, top, unlit);
  const splat::RenderImage bright = r.render(frame, splat::SplatKind::Point, top, lit);
  auto linear = [](std::uint8_t s8) {
    const float s = s8 / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
  };
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(dark.rgb[3 * centre + a], 0) << "channel " << a;
    // The nearest voxel's centre is 0.3 m under the lamp: 1 / (1 + 4 * 0.09), straight down.
    EXPECT_NEAR(linear(bright.rgb[3 * centre + a]), unlit.base[a] / (1 + 4 * 0.09f), 0.02f)
        << "channel " << a;
  }
}

// More lights in one voxel than the fixed point holds (2^31 / 16384 = 131,072 full-colour lights):
// the wrap is detected and the frame accumulated again at a coarser scale, so the voxel holds the
// CPU sum instead of a wrapped, negative one; past RGBA16F's 65504 the colour saturates there and
// the direction keeps where it points.
TEST_F(LightsGl, ACrowdedVoxelDoesNotWrap) {
  LightsDesc d = smallVolume();
  d.range = 0.1f;      // one voxel lit: fast
  d.intensity = 0.1f;  // the fixed point's step is relative to the intensity: wraps all the same
  const int count = 200000;
  // Every light a quarter voxel from the centre of voxel (4, 4, 4), on +x, intensity 0.1.
  const Vec3 centre = voxelCentre(d, 4, 4, 4);
  const Vec3 at = centre + Vec3(0.25f * d.voxelSize, 0, 0);
  std::vector<LightParticle> lights(count, light(at, Vec3(1.0f, 0.5f, 0.25f), d.intensity));
  LightVolume v(d);
  v.update(lights);
  EXPECT_TRUE(v.lastRescaled());
  EXPECT_LT(v.lastFixedScale(), fixedScale(d) / 1.5f);
  const std::size_t voxel = (4u * 8u + 4u) * 8u + 4u;
  const float dist = 0.25f * d.voxelSize;
  const float att = lightAttenuation(d, dist);
  const Texels colour = v.readColour(), direction = v.readDirection();
  const float want[3] = {count * 0.1f * att, count * 0.05f * att, count * 0.025f * att};
  for (int a = 0; a < 3; ++a)  // RGBA16F: 2^-11 relative, plus half a (coarser) step per light
    EXPECT_NEAR(colour[voxel][a], want[a], want[a] * 1e-3f + count * 0.5f / v.lastFixedScale())
        << "channel " << a;
  EXPECT_NEAR(direction[voxel][0], count * 0.1f,
              count * 0.1f * 1e-3f + count * 0.5f / v.lastFixedScale());
  EXPECT_NEAR(direction[voxel][1], 0.0f, 1e-3f);
  // A frame of few lights goes back to the fine scale.
  v.update({light(at, Vec3::Ones(), d.intensity)});
  EXPECT_FALSE(v.lastRescaled());
  EXPECT_EQ(v.lastFixedScale(), fixedScale(d));
  // Full intensity: 200,000 x 1 / att is past RGBA16F's 65504: saturated, not infinite or wrapped.
  for (LightParticle& l : lights) l = light(at, Vec3::Ones(), 1.0f);
  d.intensity = 1.0f;
  LightVolume bright(d);
  bright.update(lights);
  EXPECT_TRUE(bright.lastRescaled());
  const Texels c2 = bright.readColour(), d2 = bright.readDirection();
  EXPECT_EQ(c2[voxel][0], 65504.0f);
  EXPECT_EQ(d2[voxel][0], 65504.0f);
  EXPECT_EQ(d2[voxel][1], 0.0f);
}

// More lights than one dispatch of 65,535 groups of 64 holds (4,194,240; the paper's Table 1 goes
// to 4,194,304): the lights past it are accumulated too. The first light lights voxel (0, 0, 0),
// the last 128 voxel (7, 7, 7), the others lie far outside the volume (nothing to visit: fast).
TEST_F(LightsGl, MoreLightsThanOneDispatchAreAllAccumulated) {
  LightsDesc d = smallVolume();
  d.range = 0.1f, d.attenuation = {1.0f, 0.0f, 0.0f};
  const std::size_t count = 4194304 + 64, tail = 128;
  std::vector<LightParticle> lights(count, light(Vec3(-100, -100, -100), Vec3::Ones(), 1.0f));
  lights[0] = light(voxelCentre(d, 0, 0, 0), Vec3::Ones(), 1.0f);
  for (std::size_t i = count - tail; i < count; ++i)
    lights[i] = light(voxelCentre(d, 7, 7, 7), Vec3::Ones(), 1.0f);
  LightVolume v(d);
  v.update(lights);
  const Texels colour = v.readColour();
  EXPECT_EQ(colour[0][0], 1.0f);
  EXPECT_EQ(colour[511][0], float(tail));
}

// 24^3 voxels of 0.05 m over test::sheetSolids(), trilinear, forward.
LightsDesc sheetVolume() {
  LightsDesc d;
  d.origin = Vec3(-0.6f, -0.1f, -0.6f), d.voxelSize = 0.05f, d.voxels = {24, 24, 24};
  d.attenuation = {1.0f, 0.0f, 20.0f}, d.range = 0.3f, d.filter = LightFilter::Trilinear;
  d.specular = 0.5f, d.shininess = 16, d.roomLight = 0.3f;
  return d;
}

// lights.pipeline "deferred" (seed 004 Fig. 11): a G-buffer of the solids and the opaque water,
// then one full-screen lighting pass, gives the forward image to one 8-bit step per channel -
// solids per pixel, point splats lit at their centre either way, translucent water composited
// forward on the deferred-lit frame, depth tested against it (splats half hidden by the sphere).
TEST_F(LightsGl, DeferredGivesTheForwardImageToOneStep) {
  LightsDesc d = sheetVolume();
  const std::vector<LightParticle> lights = test::sheetLights(14);
  LightVolume forward(d);
  d.pipeline = LightPipeline::Deferred;
  LightVolume deferred(d);
  ASSERT_FALSE(forward.deferred());
  ASSERT_TRUE(deferred.deferred());
  forward.update(lights), deferred.update(lights);
  solids::SolidRenderer solids(test::sheetSolids(), Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, 0.02f);
  const splat::SplatFrame water = test::waterSheet();  // partly behind the sphere
  const int width = 160, height = 120;
  splat::SplatRenderer r(width, height);
  r.setLayers({&solids});
  const CameraDesc camera = test::sheetCamera();
  for (float alpha : {1.0f, 0.5f}) {
    splat::Lighting lighting;
    lighting.alpha = alpha;
    lighting.extra = &forward;
    const splat::RenderImage f = r.render(water, splat::SplatKind::Point, camera, lighting);
    EXPECT_EQ(r.lastPasses().lighting, 0.0);
    lighting.extra = &deferred;
    const splat::RenderImage g = r.render(water, splat::SplatKind::Point, camera, lighting);
    EXPECT_GT(r.lastPasses().lighting, 0.0) << "the lighting pass ran";
    lighting.extra = nullptr;
    const splat::RenderImage unlit = r.render(water, splat::SplatKind::Point, camera, lighting);
    const test::Steps diff = test::steps(f, g, unlit);
    EXPECT_LE(diff.worst, 1) << "alpha " << alpha;
    // The error figures' normal target: the water's coverage and normals, as forward draws them.
    lighting.extra = &forward;
    const splat::RenderImage fs = r.render(water, splat::SplatKind::Point, camera, lighting,
                                           splat::ImageContents::ColourAndNormals);
    lighting.extra = &deferred;
    const splat::RenderImage gs = r.render(water, splat::SplatKind::Point, camera, lighting,
                                           splat::ImageContents::ColourAndNormals);
    EXPECT_EQ(fs.covered, gs.covered) << "alpha " << alpha;
    float normalDiff = 0;
    for (std::size_t i = 0; i < fs.normal.size(); ++i)
      normalDiff = std::max(normalDiff, std::abs(fs.normal[i] - gs.normal[i]));
    EXPECT_LT(normalDiff, 1e-3f) << "alpha " << alpha;
    // Not two dark pictures: the particle lights (and the room light) change much of the frame.
    EXPECT_GT(diff.lit, width * height / 4) << "alpha " << alpha;
  }
}

// Shaded on the CPU (lights.shade "cpu"), the deferred frame reaches the target by a blit where
// nothing drawn after it is depth tested against it: the pixels without a surface keep the
// background, and the picture is the forward one to one step. Where the walls' points follow
// (depth tested, as forward draws them), the lighting pass restores the depth instead: a point
// behind the sphere stays hidden, one in front of it shows.
TEST_F(LightsGl, ShadedOnTheCpuTheCopyKeepsTheBackgroundAndTheDepthThatIsDrawnAgainst) {
  LightsDesc d = sheetVolume();
  const std::vector<LightParticle> lights = test::sheetLights(14);
  LightVolume forward(d);
  d.pipeline = LightPipeline::Deferred, d.accumulate = LightAccumulate::Cpu;
  d.shade = LightShade::Cpu;
  LightVolume cpu(d);
  ASSERT_TRUE(cpu.shadesOnCpu());
  forward.update(lights), cpu.update(lights);
  solids::SolidRenderer solids(test::sheetSolids(), Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, 0.02f);
  const int width = 160, height = 120;
  splat::SplatRenderer r(width, height);
  r.setLayers({&solids});
  const CameraDesc camera = test::sheetCamera();
  splat::Lighting lighting;
  lighting.background = Vec3(0.3f, 0.5f, 0.7f);
  auto picture = [&](const LightVolume& v) {
    lighting.extra = &v;
    return r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
  };
  const splat::RenderImage f = picture(forward), g = picture(cpu);
  lighting.extra = nullptr;
  const splat::RenderImage unlit =
      r.render(splat::SplatFrame{}, splat::SplatKind::Point, camera, lighting);
  const test::Steps diff = test::steps(f, g, unlit);
  EXPECT_LE(diff.worst, 1);
  EXPECT_GT(diff.lit, width * height / 4);
  std::size_t background = 0;
  for (std::size_t i = 0; i < g.rgb.size(); i += 3) {
    bool same = true;
    for (int k = 0; k < 3; ++k) same &= g.rgb[i + k] == splat::toSrgb8(lighting.background[k]);
    background += same;
  }
  EXPECT_GT(background, 500u) << "the sky beyond the floor";
  // A wall point 0.3 m behind the sphere's centre seen from the camera, and one 0.3 m before it.
  const Vec3 centre(0, 0.15f, 0), ray = (centre - camera.position).normalized();
  const Vec3 toCamera = -ray;
  auto withWall = [&](const Vec3& at) {
    r.setBoundary(
        {splat::SplatVertex{{at.x(), at.y(), at.z()}, {toCamera.x(), toCamera.y(), toCamera.z()}}},
        0.05f);
    const splat::RenderImage a = picture(forward), b = picture(cpu);
    EXPECT_LE(test::steps(a, b, a).worst, 1);
    return b;
  };
  const splat::RenderImage behind = withWall(centre + 0.3f * ray);
  const splat::RenderImage before = withWall(centre - 0.3f * ray);
  EXPECT_LE(test::steps(behind, g, g).worst, 1) << "hidden by the sphere";
  EXPECT_GE(test::steps(before, g, g).worst, 3) << "in front of it: the walls' grey shows";
}

// 4096 voxels along x is more than llvmpipe's GL_MAX_3D_TEXTURE_SIZE (2048): one line naming the
// size and the key, no GL object half made.
TEST_F(LightsGl, AVolumeGlCannotHoldIsRefusedWithTheKeyToChange) {
  LightsDesc d;
  d.voxels = {4096, 2, 2};
  try {
    LightVolume v(d);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("lights.volume.voxels"), std::string::npos) << m;
    EXPECT_NE(m.find("4096 x 2 x 2"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace sph::render::lights
