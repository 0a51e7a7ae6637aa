#include "sim/collision/Recall.h"

#include <algorithm>
#include <unordered_map>

namespace sph::collision {

std::vector<IdPair> canonicalPairs(std::vector<IdPair> pairs) {
  for (IdPair& p : pairs) {
    if (p.first > p.second) std::swap(p.first, p.second);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

Recall measureRecall(const std::vector<IdPair>& truth, const std::vector<IdPair>& seen,
                     const std::vector<std::uint32_t>& ids,
                     const std::vector<std::uint32_t>& partner) {
  constexpr std::uint32_t none = 0xFFFFFFFFu;
  auto isTrue = [&](std::uint32_t a, std::uint32_t b) {
    return std::binary_search(truth.begin(), truth.end(), IdPair(std::min(a, b), std::max(a, b)));
  };
  Recall r;
  r.truePairs = truth.size();
  for (const IdPair& p : canonicalPairs(seen)) {
    if (isTrue(p.first, p.second))
      ++r.foundPairs;
    else
      ++r.falsePairs;
  }
  std::unordered_map<std::uint32_t, std::uint32_t> chose;
  chose.reserve(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) chose[ids[i]] = partner[i];
  std::vector<std::uint32_t> colliding;
  colliding.reserve(2 * truth.size());
  for (const IdPair& p : truth) colliding.push_back(p.first), colliding.push_back(p.second);
  std::sort(colliding.begin(), colliding.end());
  colliding.erase(std::unique(colliding.begin(), colliding.end()), colliding.end());
  r.colliding = colliding.size();
  for (std::uint32_t id : colliding) {
    const auto it = chose.find(id);
    if (it != chose.end() && it->second != none) ++r.responding;
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (partner[i] == none) continue;
    ++r.chosen;
    if (isTrue(ids[i], partner[i])) ++r.chosenTrue;
    const auto it = chose.find(partner[i]);
    if (it == chose.end() || it->second == none) ++r.unanswered;
  }
  return r;
}

}  // namespace sph::collision
