// render/lights' shading of the light volume (seed 004) on the real GL (llvmpipe): each of its
// filters (extra_lights.glsl) matches a CPU evaluation of the same textures; the exact reference
// agrees with a hand-computed point and ranks trilinear above nearest.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "render/lights/ExactLights.h"
#include "render/lights/LightVolume.h"
#include "sim/lights/LightParticles.h"
#include "tests/LightTestScenes.h"
#include "tests/LightsGlTest.h"

namespace sph::render::lights {
namespace {

using test::light;
using test::LightsGl;
using test::smallVolume;
using test::Texels;

// --- The shading's filters against a CPU evaluation of the same (read-back) textures ---

struct CpuVolume {
  scene::LightsDesc d;
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
    if (d.filter == scene::LightFilter::Nearest) {
      add(1, static_cast<int>(std::floor(g.x())), static_cast<int>(std::floor(g.y())),
          static_cast<int>(std::floor(g.z())));
      return sum;
    }
    const Vec3 c = g - Vec3::Constant(0.5f);
    const int ix = static_cast<int>(std::floor(c.x())), iy = static_cast<int>(std::floor(c.y())),
              iz = static_cast<int>(std::floor(c.z()));
    const Vec3 f = c - Vec3(ix, iy, iz);
    if (d.filter == scene::LightFilter::Trilinear) {
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
  scene::LightsDesc d = smallVolume();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.8f, 0.8f);
  std::vector<sph::lights::LightParticle> lights;
  for (int i = 0; i < 40; ++i)
    lights.push_back(light(Vec3(u(rng), u(rng), u(rng)), Vec3(1, 0.7f, 0.4f), 0.8f));
  LightVolume volume(d);
  volume.update(lights);
  CpuVolume cpu{d, volume.readColour(), volume.readDirection()};
  const std::vector<ProbePoint> points = probePoints(300, 11);
  const Vec3 base(0.8f, 0.7f, 0.6f);
  for (scene::LightFilter f :
       {scene::LightFilter::Nearest, scene::LightFilter::Trilinear, scene::LightFilter::Tricubic}) {
    for (int n : {1, 2}) {
      const float tension = f == scene::LightFilter::Tricubic && n == 2 ? 1.0f : 0.0f;
      volume.setFilter(f, tension, n);
      cpu.d.filter = f, cpu.d.tension = tension, cpu.d.oversampling = n;
      const std::vector<Vec3> gpu = volume.probe(points, base);
      int lit = 0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3 want = cpu.shade(points[i], base);
        lit += want.maxCoeff() > 0.01f;
        // llvmpipe's linear filter weights are 8-bit fixed point: 1/256 of the texel values.
        const float tol = f == scene::LightFilter::Trilinear ? 2e-2f * want.norm() + 4e-3f
                                                             : 1e-4f + 1e-4f * want.norm();
        EXPECT_LT((gpu[i] - want).norm(), tol) << nameOf(f) << " x" << n << " point " << i;
      }
      EXPECT_GT(lit, 50) << nameOf(f);
    }
  }
}

// The exact reference at a point, by hand: one light 0.3 m above a point of an upward surface,
// seen from straight above: diffuse = kd base att, specular = ks att (r . v = 1).
TEST(ExactLights, OneLightOverAPointByHand) {
  scene::LightsDesc d = smallVolume();
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

// A scene far wider than 1024 ranges: lights every 4 cm along 100 m of x, range 5 cm (2,000
// ranges). At points along the whole line the sum equals that of a reference built from the
// lights within 1 m of the point alone (a scene a few ranges wide); a lookup that stopped at 1024
// cells of `range` read 0 past 51.2 m.
TEST(ExactLights, RightOverAHundredMetreScene) {
  scene::LightsDesc d = smallVolume();
  d.range = 0.05f;
  d.attenuation = {1.0f, 0.0f, 100.0f};
  std::vector<sph::lights::LightParticle> lights;
  for (int i = 0; i <= 2500; ++i)
    lights.push_back(light(Vec3(0.04f * i, 0.02f, 0.0f), Vec3(1.0f, 0.8f, 0.5f), 1.0f));
  const ExactLights exact(d, lights);
  for (float x : {0.01f, 10.0f, 51.3f, 75.55f, 99.99f}) {
    std::vector<sph::lights::LightParticle> near;
    for (const auto& l : lights) {
      if (std::abs(l.position[0] - x) < 1.0f) near.push_back(l);
    }
    const ExactLights local(d, near);
    const Vec3 p(x, 0.0f, 0.0f), eye = Vec3(0.2f, 1.0f, 0.1f).normalized();
    const LightTerms want = local.at(p, Vec3::UnitY(), eye, Vec3::Ones());
    const LightTerms got = exact.at(p, Vec3::UnitY(), eye, Vec3::Ones());
    ASSERT_GT(want.diffuse.x(), 0.0f) << "x = " << x;
    EXPECT_NEAR(got.diffuse.x(), want.diffuse.x(), 1e-6f * want.diffuse.x()) << "x = " << x;
    EXPECT_NEAR(got.specular.y(), want.specular.y(), 1e-6f * want.specular.y() + 1e-12f)
        << "x = " << x;
  }
}

// Against the exact sum over many lights above a floor, trilinear beats nearest and tricubic is
// no worse than nearest (diffuse term, PSNR over 4096 floor points).
TEST_F(LightsGl, TrilinearBeatsNearestAgainstTheExactReference) {
  scene::LightsDesc d = smallVolume();
  d.voxels = {16, 16, 16}, d.voxelSize = 0.125f;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.7f, 0.7f), height(0.08f, 0.7f);
  std::vector<sph::lights::LightParticle> lights;
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
  for (scene::LightFilter f :
       {scene::LightFilter::Nearest, scene::LightFilter::Trilinear, scene::LightFilter::Tricubic}) {
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

}  // namespace
}  // namespace sph::render::lights
