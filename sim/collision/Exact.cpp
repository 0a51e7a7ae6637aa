#include "sim/collision/Exact.h"

#include "sim/Parallel.h"

namespace sph::collision {

void ExactDetector::detect(const float* x, const float* y, const float* z, std::size_t n,
                           float range, const std::uint8_t* searching,
                           std::vector<std::uint32_t>& partner, std::vector<IndexPair>* pairs) {
  partner.assign(n, kNone);
  if (pairs) pairs->clear();
  if (n == 0) return;
  grid_.build(x, y, z, n, range, order_);
  // Sorted copies, so each neighbour range is contiguous memory.
  sx_.resize(n), sy_.resize(n), sz_.resize(n);
  parallelFor(n, [&](std::size_t k) {
    sx_[k] = x[order_[k]], sy_[k] = y[order_[k]], sz_[k] = z[order_[k]];
  });
  const double range2 = static_cast<double>(range) * range;
  std::vector<std::vector<IndexPair>> threadPairs(pairs ? static_cast<std::size_t>(threadCount())
                                                        : 0);
  parallelForDynamic(n, 256, [&](std::size_t k) {
    const std::uint32_t i = order_[k];
    const bool search = !searching || searching[i];
    if (!search && !pairs) return;
    const float px = sx_[k], py = sy_[k], pz = sz_[k];
    double best = range2;
    std::uint32_t bestIndex = kNone;
    grid_.forEachNeighbourRange(
        grid_.cellOf(px, py, pz), [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t m = begin; m < end; ++m) {
            if (m == k) continue;
            const double d2 = distance2(px, py, pz, sx_[m], sy_[m], sz_[m]);
            if (!(d2 < range2)) continue;
            if (pairs && i < order_[m])
              threadPairs[static_cast<std::size_t>(threadIndex())].emplace_back(i, order_[m]);
            if (d2 < best || (d2 == best && order_[m] < bestIndex))
              best = d2, bestIndex = order_[m];
          }
        });
    if (search) partner[i] = bestIndex;
  });
  if (pairs) {
    for (const auto& t : threadPairs) pairs->insert(pairs->end(), t.begin(), t.end());
  }
}

}  // namespace sph::collision
