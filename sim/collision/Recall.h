// Recall of a collision method against `exact` (DESIGN.md, "Reference and baselines"): which of
// the true colliding pairs (closer than collision_range) a method found, per pair and per
// particle, and how its responses pair up (the paper's failure mode 2: one-sided responses).
// Used by tests/test_collision.cpp and bench/collision/ (bench_collision).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace sph::collision {

using IdPair = std::pair<std::uint32_t, std::uint32_t>;

// Pairs as (smaller id, larger id), sorted, without duplicates.
std::vector<IdPair> canonicalPairs(std::vector<IdPair> pairs);

struct Recall {
  std::size_t truePairs = 0;   // pairs closer than range (exact)
  std::size_t foundPairs = 0;  // of them, seen by the method (either particle saw the other)
  std::size_t falsePairs = 0;  // seen pairs that are not true pairs (curr_pos from the texel)
  std::size_t colliding = 0;   // particles with at least one true partner
  std::size_t responding = 0;  // of them, particles that chose a partner
  std::size_t chosen = 0;      // particles that chose a partner
  std::size_t chosenTrue = 0;  // of them, a true partner
  std::size_t unanswered = 0;  // chose j while j chose nobody: only one side of the pair reacts

  double pairRecall() const { return truePairs ? double(foundPairs) / double(truePairs) : 1.0; }
  double particleRecall() const { return colliding ? double(responding) / double(colliding) : 1.0; }
  double partnerPrecision() const { return chosen ? double(chosenTrue) / double(chosen) : 1.0; }
  double unansweredFraction() const { return chosen ? double(unanswered) / double(chosen) : 0.0; }
};

// truth: the true pairs (ids, canonical); seen: the pairs the method saw (ids, any order);
// partner[i]: the id particle ids[i] chose, or 0xFFFFFFFF for none.
Recall measureRecall(const std::vector<IdPair>& truth, const std::vector<IdPair>& seen,
                     const std::vector<std::uint32_t>& ids,
                     const std::vector<std::uint32_t>& partner);

}  // namespace sph::collision
