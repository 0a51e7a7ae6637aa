// The exact particle lighting the volume approximates (docs/lights.md, "Error figures"): at a
// point, the sum over every light within `range` of its own attenuated Phong diffuse and
// specular, with the light vector to that light - no voxels, no filter. CPU, lights binned in
// cells `range` wide so a point visits its 27 cells only; only the cells that hold lights are
// kept (sorted keys), so a scene of any extent costs memory by its lights, not its volume. The
// seed has no ground truth; this one turns each filter / oversampling / voxel size into an error
// figure.
#pragma once

#include <cstdint>
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
  std::vector<sph::lights::LightParticle> lights_;  // sorted by cell key
  std::vector<std::uint64_t> keys_;                 // the cells that hold lights, ascending
  std::vector<std::size_t> cellStart_;  // lights of keys_[k]: [cellStart_[k], cellStart_[k + 1])
  Vec3 lo_ = Vec3::Zero();
  float cellSize_ = 1;
  std::uint64_t keyOf(std::int64_t cx, std::int64_t cy, std::int64_t cz) const;
};

// Error figures of an approximation against the exact values, over the same points: colours in
// [0, 1] (clamped) as 8-bit-free floats; PSNR in dB with peak 1, mean absolute error per channel.
struct LightError {
  double psnr = 0, meanAbs = 0;
};
LightError lightError(const std::vector<Vec3>& approx, const std::vector<Vec3>& exact);

}  // namespace sph::render::lights
