// exact: every pair closer than collision_range, found with a uniform grid of cell = range
// (sim/grid/NeighbourGrid.h): a pair can only be in the same or adjacent cells. The ground truth that
// recall is measured against, and the time baseline against the thesis's octree.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/grid/NeighbourGrid.h"
#include "sim/collision/Detector.h"

namespace sph::collision {

class ExactDetector final : public Detector {
 public:
  std::string name() const override { return enumName(scene::CollisionMethod::Exact); }
  void detect(const float* x, const float* y, const float* z, std::size_t n, float range,
              const std::uint8_t* searching, std::vector<std::uint32_t>& partner,
              std::vector<IndexPair>* pairs) override;

 private:
  grid::NeighbourGrid grid_;
  std::vector<std::uint32_t> order_;
  std::vector<float> sx_, sy_, sz_;
};

}  // namespace sph::collision
