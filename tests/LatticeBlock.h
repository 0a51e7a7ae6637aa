// A lattice block of particles for the renderer's tests (tests/test_splats.cpp,
// tests/test_splat_gl.cpp): nx x ny x nz particles at spacing dx from the origin, and the
// renderer's density field over them.
#pragma once

#include <vector>

#include "render/splat/DensityField.h"

namespace sph::render::splat::test {

struct Block {
  std::vector<float> x, y, z;
  Block(int nx, int ny, int nz, float dx) {
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          x.push_back((i + 0.5f) * dx), y.push_back((j + 0.5f) * dx), z.push_back((k + 0.5f) * dx);
        }
  }
  DensityField field(float dx, float radius = 2.5f) const {
    return DensityField(x.data(), y.data(), z.data(), x.size(), dx, radius);
  }
};

}  // namespace sph::render::splat::test
