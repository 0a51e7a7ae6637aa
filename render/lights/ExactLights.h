// The exact particle lighting the volume approximates (docs/lights.md, "Error figures"): at a
// point, the sum over every light within `range` of its own attenuated Phong diffuse and
// specular, with the light vector to that light - no voxels, no filter. CPU, lights binned in a
// uniform grid of cells `range` wide so a point visits its 27 cells only. The seed has no ground
// truth; this one turns each filter / oversampling / voxel size into an error figure.
#pragma once

#include <vector>

#include "sim/lights/LightParticles.h"
#include "sim/scene/LightsDesc.h"

namespace sph::render::lights {

struct LightTerms {
  Vec3 diffuse = Vec3::Zero(), specular = Vec3::Zero();
};

class ExactLights {
 public:
  ExactLights(const scene::LightsDesc& desc, const std::vector<sph::lights::LightParticle>& lights);
  // The particle lights at `position` with unit normal `n`, unit `toEye`, surface colour `base`,
  // with desc's diffuse, specular and shininess (the same terms as shaders/extra_lights.glsl).
  LightTerms at(const Vec3& position, const Vec3& n, const Vec3& toEye, const Vec3& base) const;

 private:
  scene::LightsDesc desc_;
  std::vector<sph::lights::LightParticle> lights_;  // sorted by cell
  std::vector<std::size_t> cellStart_;  // lights of cell c: [cellStart_[c], cellStart_[c + 1])
  Vec3 lo_;
  std::array<int, 3> cells_{};
  float cellSize_ = 1;
  int cellOf(const Vec3& p, int axis) const;
};

// Error figures of an approximation against the exact values, over the same points: colours in
// [0, 1] (clamped) as 8-bit-free floats; PSNR in dB with peak 1, mean absolute error per channel.
struct LightError {
  double psnr = 0, meanAbs = 0;
};
LightError lightError(const std::vector<Vec3>& approx, const std::vector<Vec3>& exact);

}  // namespace sph::render::lights
