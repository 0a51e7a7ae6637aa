// render/lights' light volume (seed 004) on the real GL (llvmpipe): one light in an empty volume
// gives the attenuation formula at voxel centres; the race-free accumulation equals a CPU sum of
// many lights, where the paper's unsynchronised read-modify-write loses light; a voxel more lights
// share than the fixed point holds, and more lights than one dispatch holds, are accumulated
// whole; a volume GL cannot hold is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "render/lights/LightVolume.h"
#include "sim/InputError.h"
#include "sim/lights/LightParticles.h"
#include "tests/LightTestScenes.h"
#include "tests/LightsGlTest.h"

namespace sph::render::lights {
namespace {

using test::light;
using test::LightsGl;
using test::smallVolume;
using test::Texels;
using test::voxelCentre;

// The CPU sum the volume should hold: colour texture (rgb) and direction texture (xyz).
void cpuSums(const scene::LightsDesc& d, const std::vector<sph::lights::LightParticle>& lights,
             Texels& colour, Texels& direction) {
  colour.assign(d.voxelCount(), {0, 0, 0, 0});
  direction.assign(d.voxelCount(), {0, 0, 0, 0});
  for (int z = 0; z < d.voxels[2]; ++z)
    for (int y = 0; y < d.voxels[1]; ++y)
      for (int x = 0; x < d.voxels[0]; ++x) {
        const std::size_t v = (static_cast<std::size_t>(z) * d.voxels[1] + y) * d.voxels[0] + x;
        const Vec3 c = voxelCentre(d, x, y, z);
        for (const sph::lights::LightParticle& l : lights) {
          const Vec3 p(l.position[0], l.position[1], l.position[2]);
          const float dist = (p - c).norm();
          const float att = sph::lights::lightAttenuation(d, dist);
          if (att == 0) continue;
          for (int a = 0; a < 3; ++a) {
            colour[v][static_cast<std::size_t>(a)] += att * l.colour[static_cast<std::size_t>(a)];
            if (dist > 0)
              direction[v][static_cast<std::size_t>(a)] += (p - c)[a] / dist * l.colour[3];
          }
        }
      }
}

// Seed 004 eq. 1 with the text's parentheses, 1 / (c + l d + q d^2), at every voxel centre within
// range, zero beyond; the direction texture holds the unit vector to the light times intensity.
// Stored as RGBA16F (the paper's format): relative precision 2^-11, plus the fixed-point step.
TEST_F(LightsGl, OneLightGivesTheAttenuationFormulaAtVoxelCentres) {
  for (scene::LightAccumulate mode :
       {scene::LightAccumulate::Atomic, scene::LightAccumulate::Paper}) {
    scene::LightsDesc d = smallVolume();
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
  scene::LightsDesc d = smallVolume();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.2f, 0.2f);
  std::vector<sph::lights::LightParticle> lights;
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
  d.accumulate = scene::LightAccumulate::Paper;
  LightVolume paper(d);
  paper.update(lights);
  for (const auto& t : paper.readColour()) paperTotal += t[0] + t[1] + t[2];
  EXPECT_NEAR(atomicTotal / cpuTotal, 1.0, 1e-3);
  EXPECT_LT(paperTotal / cpuTotal, 0.9)
      << "the paper's race loses updates: " << paperTotal / cpuTotal;
}

// More lights in one voxel than the fixed point holds (2^31 / 16384 = 131,072 full-colour lights):
// the wrap is detected and the frame accumulated again at a coarser scale, so the voxel holds the
// CPU sum instead of a wrapped, negative one; past RGBA16F's 65504 the colour saturates there and
// the direction keeps where it points.
TEST_F(LightsGl, ACrowdedVoxelDoesNotWrap) {
  scene::LightsDesc d = smallVolume();
  d.range = 0.1f;      // one voxel lit: fast
  d.intensity = 0.1f;  // the fixed point's step is relative to the intensity: wraps all the same
  const int count = 200000;
  // Every light a quarter voxel from the centre of voxel (4, 4, 4), on +x, intensity 0.1.
  const Vec3 centre = voxelCentre(d, 4, 4, 4);
  const Vec3 at = centre + Vec3(0.25f * d.voxelSize, 0, 0);
  std::vector<sph::lights::LightParticle> lights(count,
                                                 light(at, Vec3(1.0f, 0.5f, 0.25f), d.intensity));
  LightVolume v(d);
  v.update(lights);
  EXPECT_TRUE(v.lastRescaled());
  EXPECT_LT(v.lastFixedScale(), fixedScale(d) / 1.5f);
  const std::size_t voxel = (4u * 8u + 4u) * 8u + 4u;
  const float dist = 0.25f * d.voxelSize;
  const float att = sph::lights::lightAttenuation(d, dist);
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
  for (sph::lights::LightParticle& l : lights) l = light(at, Vec3::Ones(), 1.0f);
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
  scene::LightsDesc d = smallVolume();
  d.range = 0.1f, d.attenuation = {1.0f, 0.0f, 0.0f};
  const std::size_t count = 4194304 + 64, tail = 128;
  std::vector<sph::lights::LightParticle> lights(count,
                                                 light(Vec3(-100, -100, -100), Vec3::Ones(), 1.0f));
  lights[0] = light(voxelCentre(d, 0, 0, 0), Vec3::Ones(), 1.0f);
  for (std::size_t i = count - tail; i < count; ++i)
    lights[i] = light(voxelCentre(d, 7, 7, 7), Vec3::Ones(), 1.0f);
  LightVolume v(d);
  v.update(lights);
  const Texels colour = v.readColour();
  EXPECT_EQ(colour[0][0], 1.0f);
  EXPECT_EQ(colour[511][0], float(tail));
}

// 4096 voxels along x is more than llvmpipe's GL_MAX_3D_TEXTURE_SIZE (2048): one line naming the
// size and the key, no GL object half made.
TEST_F(LightsGl, AVolumeGlCannotHoldIsRefusedWithTheKeyToChange) {
  scene::LightsDesc d;
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
