// cdt-gl against its reference cdt-cpu (DESIGN.md, "Reference and baselines"): the same inputs
// must give the same texture (every texel's particle and key), the same colliding set (every
// particle's partner and candidate count) and the same outputs to 1e-5, for the paper's settings
// and for each improvement, in the paper's own loop (integrate) and after an SPH integration.
// Runs for real on the machine's GL (Mesa llvmpipe in CI).
#include <gtest/gtest.h>

#include <cmath>

#include "render/cdt/CdtGl.h"
#include "render/gl/GlContext.h"
#include "sim/cdt/CdtCpu.h"
#include "tests/CdtTestScenes.h"

namespace sph {
namespace {

struct Variant {
  const char* name;
  void (*configure)(scene::CollisionDesc&);
  bool integrate;
};

void compareStep(const Particles& cpu, const Particles& gl,
                 const std::vector<cdt::Diagnostics>& cpuDiag,
                 const std::vector<cdt::Diagnostics>& glDiag, const char* what) {
  ASSERT_EQ(cpuDiag.size(), glDiag.size());
  std::size_t partnerMismatch = 0, countMismatch = 0, texelMismatch = 0, colliding = 0;
  for (std::size_t i = 0; i < cpuDiag.size(); ++i) {
    partnerMismatch += cpuDiag[i].partner != glDiag[i].partner;
    countMismatch += cpuDiag[i].candidates != glDiag[i].candidates;
    texelMismatch +=
        cpuDiag[i].texel != glDiag[i].texel || cpuDiag[i].texelRange != glDiag[i].texelRange;
    colliding += cpuDiag[i].partner != cdt::kNoPartner;
  }
  EXPECT_EQ(partnerMismatch, 0u) << what << ": particles whose partner differs";
  EXPECT_EQ(countMismatch, 0u) << what << ": particles whose candidate count differs";
  EXPECT_EQ(texelMismatch, 0u) << what << ": particles whose base texel or r differs";
  double worst = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    ASSERT_EQ(cpu.id[i], gl.id[i]);
    for (auto [a, b] : {std::pair{cpu.x[i], gl.x[i]},
                        {cpu.y[i], gl.y[i]},
                        {cpu.z[i], gl.z[i]},
                        {cpu.vx[i], gl.vx[i]},
                        {cpu.vy[i], gl.vy[i]},
                        {cpu.vz[i], gl.vz[i]},
                        {cpu.collideTime[i], gl.collideTime[i]}}) {
      worst = std::max(worst, static_cast<double>(std::fabs(a - b)));
    }
  }
  EXPECT_LE(worst, 1e-5) << what << ": largest output difference";
  std::printf("    %s: %zu colliding particles, largest output difference %.3g\n", what, colliding,
              worst);
}

void compareTextures(const cdt::Texture& cpu, const cdt::Texture& gl, const char* what) {
  ASSERT_EQ(cpu.texels.size(), gl.texels.size());
  std::size_t differ = 0, occupied = 0;
  for (std::size_t t = 0; t < cpu.texels.size(); ++t) {
    occupied += cpu.texels[t][3] >= 0;
    differ += cpu.keys[t] != gl.keys[t] || cpu.texels[t] != gl.texels[t];
  }
  EXPECT_EQ(differ, 0u) << what << ": texels that differ (of " << occupied << " occupied)";
}

class CdtGlAgreement : public ::testing::TestWithParam<Variant> {};

TEST_P(CdtGlAgreement, SameTextureCollisionsAndOutputs) {
  const Variant& v = GetParam();
  render::gl::GlContext context = render::gl::GlContext::headless();
  scene::CollisionDesc desc = test::testCollision();
  v.configure(desc);
  const cdt::Settings settings = cdt::makeSettings(desc, std::nullopt);
  cdt::CdtCpu cpu(settings);
  render::cdt::CdtGl gl(settings);
  Particles pc = test::randomParticles(20000, 0.5f, 11);
  Particles pg = pc;
  const float dt = 0.004f;
  gl.upload(pg);
  std::size_t collided = 0;
  for (int step = 0; step < 4; ++step) {
    cpu.step(pc, dt, v.integrate);
    gl.step(dt, v.integrate);
    gl.download(pg);
    const std::string what = std::string(v.name) + " step " + std::to_string(step);
    compareStep(pc, pg, cpu.diagnostics(), gl.diagnostics(), what.c_str());
    compareTextures(cpu.texture(), gl.readTexture(), what.c_str());
    for (const cdt::Diagnostics& d : cpu.diagnostics()) collided += d.partner != cdt::kNoPartner;
    if (::testing::Test::HasFailure()) return;
    if (!v.integrate) {
      // The SPH step integrates between passes (on the CPU): the same inputs go to both. In the
      // paper's loop (integrate) the GL state never leaves the GPU: its ping-pong buffers and
      // textures carry it from step to step.
      for (std::size_t i = 0; i < pc.size(); ++i) {
        pc.vx[i] += dt * pc.ax[i], pc.vy[i] += dt * pc.ay[i], pc.vz[i] += dt * pc.az[i];
        pc.x[i] += dt * pc.vx[i], pc.y[i] += dt * pc.vy[i], pc.z[i] += dt * pc.vz[i];
      }
      pg = pc;
      gl.upload(pg);
    }
  }
  EXPECT_GT(collided, 500u) << "the set-up must produce collisions to compare";
}

// More particles than one dispatch of the texture write covers (65,535 groups of 64): the GL
// texture still holds every texel's winner as cdt-cpu's does. Before the write was split into
// several dispatches, the one dispatch failed and the texture was empty.
TEST(CdtGlLarge, MoreParticlesThanOneDispatchCovers) {
  render::gl::GlContext context = render::gl::GlContext::headless();
  scene::CollisionDesc desc = test::testCollision();
  const cdt::Settings settings = cdt::makeSettings(desc, std::nullopt);
  cdt::CdtCpu cpu(settings);
  render::cdt::CdtGl gl(settings);
  Particles pc = test::randomParticles(std::size_t{65535} * 64 + 5000, 0.5f, 13);
  gl.upload(pc);
  cpu.step(pc, 0.004f, false);
  gl.step(0.004f, false);
  compareTextures(cpu.texture(), gl.readTexture(), "4.2M particles");
}

INSTANTIATE_TEST_SUITE_P(
    Variants, CdtGlAgreement,
    ::testing::Values(
        Variant{"paper",
                [](scene::CollisionDesc& c) {
                  c.response = scene::CollisionResponse::Paper;
                  c.positionSource = scene::CdtPositionSource::Texel;
                  c.cooldown = 0.05f;
                },
                true},
        Variant{"separate", [](scene::CollisionDesc&) {}, false},
        Variant{"adaptive",
                [](scene::CollisionDesc& c) { c.adaptiveTexelRange = true, c.maxTexelRange = 3; },
                false},
        Variant{"layers", [](scene::CollisionDesc& c) { c.layers = 3; }, true},
        Variant{"wide",
                [](scene::CollisionDesc& c) {
                  c.texelRange = 2, c.response = scene::CollisionResponse::Paper;
                },
                false},
        // The paper's texture write (rasterised points, depth test) gives the same texture.
        Variant{"raster",
                [](scene::CollisionDesc& c) { c.textureWrite = scene::CdtTextureWrite::Raster; },
                true},
        Variant{"raster_layers",
                [](scene::CollisionDesc& c) {
                  c.textureWrite = scene::CdtTextureWrite::Raster;
                  c.layers = 4;
                  c.response = scene::CollisionResponse::Paper;
                },
                false}),
    [](const ::testing::TestParamInfo<Variant>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace sph
