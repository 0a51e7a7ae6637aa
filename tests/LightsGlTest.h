// The volume and the GL context the render/lights suites test_lights, test_lights_volume and
// test_lights_filters share: 8^3 voxels of 0.25 m, its voxel centres, read-back texels, and a
// headless context for each test.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <vector>

#include "render/gl/GlContext.h"
#include "sim/scene/LightsDesc.h"

namespace sph::test {

// A 3D texture read back: one RGBA float per voxel, x fastest.
using Texels = std::vector<std::array<float, 4>>;

// 8^3 voxels of 0.25 m from (-1, -1, -1).
inline scene::LightsDesc smallVolume() {
  scene::LightsDesc d;
  d.origin = Vec3(-1, -1, -1);
  d.voxelSize = 0.25f;
  d.voxels = {8, 8, 8};
  d.attenuation = {1.0f, 0.5f, 2.0f};
  d.range = 0.6f;
  return d;
}

inline Vec3 voxelCentre(const scene::LightsDesc& d, int x, int y, int z) {
  return d.origin + d.voxelSize * Vec3(x + 0.5f, y + 0.5f, z + 0.5f);
}

class LightsGl : public ::testing::Test {
 protected:
  void SetUp() override {
    context_ = std::make_unique<render::gl::GlContext>(render::gl::GlContext::headless());
  }
  std::unique_ptr<render::gl::GlContext> context_;
};

}  // namespace sph::test
