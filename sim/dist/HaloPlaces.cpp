// Halo::globalPlaces: each owned particle's index in the single-process order, from every rank's
// keys (docs/scaling.md, "What is bit-identical": the global order is the order of the keys).
#include <algorithm>
#include <chrono>
#include <cstring>

#include "sim/Assert.h"
#include "sim/dist/Halo.h"

namespace sph::dist {

std::vector<std::uint64_t> Halo::globalPlaces() {
  SPH_ASSERT(ghost_.empty());
  const auto start = std::chrono::steady_clock::now();
  Bytes mine(keys_.size() * sizeof(std::uint64_t));
  if (!keys_.empty()) std::memcpy(mine.data(), keys_.data(), mine.size());
  const std::vector<Bytes> all = comm_.allGather(mine);
  std::vector<std::uint64_t> places(keys_.size(), 0);
  std::vector<std::uint64_t> theirs;
  for (const Bytes& b : all) stats_.placesBytesReceived += b.size();
  stats_.placesBytesReceived -= mine.size();
  for (const Bytes& b : all) {
    theirs.resize(b.size() / sizeof(std::uint64_t));
    if (!theirs.empty()) std::memcpy(theirs.data(), b.data(), b.size());
    // A rank's arrays are in key order but for the particles it emitted since its last sort.
    std::sort(theirs.begin(), theirs.end());
    // Keys are unique across ranks: a particle's place is the count of smaller keys everywhere.
    for (std::size_t i = 0; i < keys_.size(); ++i)
      places[i] += static_cast<std::uint64_t>(
          std::lower_bound(theirs.begin(), theirs.end(), keys_[i]) - theirs.begin());
  }
  stats_.placesCalls += 1;
  stats_.placesSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return places;
}

}  // namespace sph::dist
