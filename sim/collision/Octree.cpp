#include "sim/collision/Octree.h"

#include "sim/Parallel.h"

namespace sph::collision {

OctreeDetector::OctreeDetector(const Vec3& centre, float rootSize, int depth) {
  Node root;
  for (int k = 0; k < 3; ++k)
    root.lo[k] = centre[k] - 0.5f * rootSize, root.hi[k] = centre[k] + 0.5f * rootSize;
  nodes_.push_back(root);
  // Breadth first, so the nodes of one depth are consecutive (the thesis's 1-D node array).
  std::size_t levelBegin = 0, levelEnd = 1;
  for (int d = 0; d < depth; ++d) {
    for (std::size_t i = levelBegin; i < levelEnd; ++i) {
      nodes_[i].firstChild = static_cast<std::int32_t>(nodes_.size());
      const Node parent = nodes_[i];
      for (int c = 0; c < 8; ++c) {
        Node child;
        for (int k = 0; k < 3; ++k) {
          const float mid = 0.5f * (parent.lo[k] + parent.hi[k]);
          const bool upper = (c >> k) & 1;
          child.lo[k] = upper ? mid : parent.lo[k];
          child.hi[k] = upper ? parent.hi[k] : mid;
        }
        nodes_.push_back(child);
      }
    }
    levelBegin = levelEnd;
    levelEnd = nodes_.size();
  }
  for (std::size_t i = levelBegin; i < levelEnd; ++i)
    nodes_[i].leaf = static_cast<std::int32_t>(leafCount_++);
}

int OctreeDetector::leafOf(float px, float py, float pz) const {
  const float p[3] = {px, py, pz};
  auto inside = [&](const Node& node) {
    // Half-open boxes, so a point on a shared face belongs to exactly one child.
    for (int k = 0; k < 3; ++k) {
      if (!(p[k] >= node.lo[k] && p[k] < node.hi[k])) return false;
    }
    return true;
  };
  if (!inside(nodes_[0])) return -1;
  std::size_t node = 0;
  while (nodes_[node].firstChild >= 0) {
    std::size_t next = nodes_.size();
    for (int c = 0; c < 8; ++c) {
      const std::size_t child = static_cast<std::size_t>(nodes_[node].firstChild + c);
      if (inside(nodes_[child])) {
        next = child;
        break;
      }
    }
    if (next == nodes_.size()) return -1;  // rounding at a midpoint: treat as outside
    node = next;
  }
  return nodes_[node].leaf;
}

void OctreeDetector::detect(const float* x, const float* y, const float* z, std::size_t n,
                            float range, const std::uint8_t* searching,
                            std::vector<std::uint32_t>& partner, std::vector<IndexPair>* pairs) {
  partner.assign(n, kNone);
  if (pairs) pairs->clear();
  // Octree pass: put every particle into its leaf (walks in parallel, lists by counting sort).
  leafOfPoint_.resize(n);
  parallelFor(n, [&](std::size_t i) { leafOfPoint_[i] = leafOf(x[i], y[i], z[i]); });
  leafStart_.assign(leafCount_ + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (leafOfPoint_[i] >= 0) ++leafStart_[static_cast<std::size_t>(leafOfPoint_[i]) + 1];
  }
  for (std::size_t l = 0; l < leafCount_; ++l) leafStart_[l + 1] += leafStart_[l];
  leafItems_.resize(leafStart_[leafCount_]);
  cursor_.assign(leafStart_.begin(), leafStart_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (leafOfPoint_[i] >= 0)
      leafItems_[cursor_[static_cast<std::size_t>(leafOfPoint_[i])]++] =
          static_cast<std::uint32_t>(i);
  }
  // Particle pass: walk to the leaf again (as the thesis's compute shader does) and test every
  // particle in it.
  const double range2 = static_cast<double>(range) * range;
  std::vector<std::vector<IndexPair>> threadPairs(pairs ? static_cast<std::size_t>(threadCount())
                                                        : 0);
  parallelForDynamic(n, 64, [&](std::size_t i) {
    const bool search = !searching || searching[i];
    if (!search && !pairs) return;
    const int leaf = leafOf(x[i], y[i], z[i]);
    if (leaf < 0) return;
    double best = range2;
    std::uint32_t bestIndex = kNone;
    for (std::uint32_t m = leafStart_[static_cast<std::size_t>(leaf)];
         m < leafStart_[static_cast<std::size_t>(leaf) + 1]; ++m) {
      const std::uint32_t j = leafItems_[m];
      if (j == i) continue;
      const double d2 = distance2(x[i], y[i], z[i], x[j], y[j], z[j]);
      if (!(d2 < range2)) continue;
      if (pairs && i < j)
        threadPairs[static_cast<std::size_t>(threadIndex())].emplace_back(
            static_cast<std::uint32_t>(i), j);
      if (d2 < best || (d2 == best && j < bestIndex)) best = d2, bestIndex = j;
    }
    if (search) partner[i] = bestIndex;
  });
  if (pairs) {
    for (const auto& t : threadPairs) pairs->insert(pairs->end(), t.begin(), t.end());
  }
}

}  // namespace sph::collision
