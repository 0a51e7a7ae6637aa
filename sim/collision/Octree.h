// octree: the thesis's baseline (seed 001, section 5, Table 5-1): a full octree of fixed depth
// (3: 512 leaves) over a cubic root (the thesis: 50 x 50 x 50), rebuilt every step from the
// particle positions; each particle walks from the root to the leaf that contains it, testing the
// children's boxes in turn, and collides with the nearest particle of that leaf only. Pairs split
// by a leaf boundary are never found, and the cost per particle grows with its leaf's population:
// the reasons it is slower and less exact than `exact`.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sim/Types.h"
#include "sim/collision/Detector.h"

namespace sph::collision {

class OctreeDetector final : public Detector {
 public:
  // Root cube of edge `rootSize` (m) centred at `centre`, subdivided `depth` times.
  OctreeDetector(const Vec3& centre, float rootSize, int depth);
  std::string name() const override { return enumName(scene::CollisionMethod::Octree); }
  void detect(const float* x, const float* y, const float* z, std::size_t n, float range,
              const std::uint8_t* searching, std::vector<std::uint32_t>& partner,
              std::vector<IndexPair>* pairs) override;

  std::size_t nodeCount() const { return nodes_.size(); }
  std::size_t leafCount() const { return leafCount_; }
  // Leaf holding a point (its index among the leaves), or -1 outside the root: the walk itself.
  int leafOf(float px, float py, float pz) const;

 private:
  // One node as the thesis lays them out in an array: its box, where its children start, and for
  // leaves their number (particle lists are rebuilt per step in leafStart_/leafItems_).
  struct Node {
    std::array<float, 3> lo, hi;
    std::int32_t firstChild = -1;  // index of 8 consecutive children, -1 for a leaf
    std::int32_t leaf = -1;        // leaf number
  };
  std::vector<Node> nodes_;
  std::size_t leafCount_ = 0;
  std::vector<std::int32_t> leafOfPoint_;
  std::vector<std::uint32_t> leafStart_, leafItems_, cursor_;
};

}  // namespace sph::collision
