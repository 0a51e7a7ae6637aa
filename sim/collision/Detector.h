// The CPU collision methods that find partners in 3D (exact, octree) share one shape: a Detector
// finds, for each searching particle, its nearest other particle within range at the start of the
// step, and DetectorPass turns that into the step's collision pass with the same response as the
// CDT methods (sim/collision/Response.h). So methods differ only in what they detect.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/scene/CollisionDesc.h"
#include "sim/CollisionPass.h"
#include "sim/collision/Response.h"

namespace sph::collision {

inline constexpr std::uint32_t kNone = 0xFFFFFFFFu;
using IndexPair = std::pair<std::uint32_t, std::uint32_t>;

class Detector {
 public:
  virtual ~Detector() = default;
  virtual std::string name() const = 0;
  // For each i with searching[i] (all if null): partner[i] = index of the nearest other point
  // closer than `range` (m), kNone if there is none. With `pairs`, also every pair (i < j) closer
  // than range that the method examined - all of them for exact, those inside one leaf for octree.
  virtual void detect(const float* x, const float* y, const float* z, std::size_t n, float range,
                      const std::uint8_t* searching, std::vector<std::uint32_t>& partner,
                      std::vector<IndexPair>* pairs) = 0;
};

// Squared distance of two points in double on float coordinates (exact products), the predicate
// every CPU method and the CDT use: d2 < range^2 collides.
inline double distance2(float ax, float ay, float az, float bx, float by, float bz) {
  const double dx = static_cast<double>(ax) - static_cast<double>(bx);
  const double dy = static_cast<double>(ay) - static_cast<double>(by);
  const double dz = static_cast<double>(az) - static_cast<double>(bz);
  return dx * dx + dy * dy + dz * dz;
}

// A detector as the step's collision pass: reconstructs the start of the step (x - v dt), lets
// particles out of cooldown search, and responds like the CDT methods.
class DetectorPass final : public CollisionPass {
 public:
  DetectorPass(std::unique_ptr<Detector> detector, const scene::CollisionDesc& desc);
  std::string name() const override { return detector_->name(); }
  void apply(Particles& particles, const CollisionContext& context) override;

 private:
  std::unique_ptr<Detector> detector_;
  scene::CollisionDesc desc_;
  std::vector<float> x0_, y0_, z0_;
  std::vector<std::uint8_t> searching_;
  std::vector<std::uint32_t> partner_;
};

}  // namespace sph::collision
