// Halo::globalPlaces: each owned particle's index in the single-process order (the order of the
// keys, docs/scaling.md "What is bit-identical"), without gathering every key.
//
// A key made by sorted() names its cell of the key lattice, row-major (x fastest). Call a "unit"
// the cells that share the coordinates above the slab axis: a row of cells along x when the slabs
// cut x, a z plane when they cut y, the whole lattice when they cut z. A unit's cells are
// consecutive keys ordered first by the slab axis, and the slabs are whole planes along that axis
// in rank order, so within a unit every key of rank r is below every key of rank r + 1. For a
// particle of rank r in unit u therefore
//   place = (keys of the units below u, on every rank) + (keys of u on the ranks below r)
//           + (its index among rank r's keys of u),
// which one sum and one exclusive scan over the ranks of a counter per unit give.
//
// That holds for the keys whose cell is in this rank's slab of the cut sorted() keyed them with.
// The others, "strays", are gathered: particles that migrated since (the `exact` collision pass's
// second exchange, a migration-only step of the particle model), those emitted since (kEmitted),
// and every key before the first sort (the starting order). Every rank receives every stray key
// and counts its in-order keys below each (one more sum); a stray's place is that count over the
// ranks plus its index among the strays.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <limits>
#include <numeric>

#include "sim/Assert.h"
#include "sim/dist/Halo.h"

namespace sph::dist {
namespace {

constexpr std::int64_t kStray = -1;

}  // namespace

std::vector<std::uint64_t> Halo::globalPlaces() {
  SPH_ASSERT(ghost_.empty());
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = keys_.size();
  const int axis = keyedSlabs_.axis;
  const long long d0 = keyedLattice_.dims[0], d1 = keyedLattice_.dims[1];
  const long long lo = keyed_ ? keyedSlabs_.first[rank()] : 0;
  const long long hi = keyed_ ? keyedSlabs_.first[rank() + 1] : 0;
  long long lastLinear = -1;  // the keys come in order, a cell's after each other: decode once
  std::int64_t lastUnit = kStray;
  const auto unitOf = [&](std::uint64_t key) -> std::int64_t {
    if (!keyed_ || (key & kEmitted)) return kStray;
    const auto linear = static_cast<long long>(key >> kWithinBits);
    if (linear == lastLinear) return lastUnit;
    const long long c[3] = {linear % d0, linear / d0 % d1, linear / d0 / d1};
    const long long plane = c[axis] + keyedLattice_.origin[axis];
    lastLinear = linear;
    lastUnit = plane < lo || plane >= hi ? kStray : axis == 0 ? linear / d0 : axis == 1 ? c[2] : 0;
    return lastUnit;
  };

  // This rank's keys in key order (the arrays are, but for particles emitted since the sort).
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  if (!std::is_sorted(keys_.begin(), keys_.end()))
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return keys_[a] < keys_[b]; });
  std::vector<std::int64_t> unit(n);
  std::vector<std::uint64_t> myStrays;  // in key order
  constexpr double kNone = std::numeric_limits<double>::infinity();
  std::vector<double> span{kNone, kNone};  // the lowest unit and minus the highest
  for (std::uint32_t i : order) {
    unit[i] = unitOf(keys_[i]);
    if (unit[i] == kStray) {
      myStrays.push_back(keys_[i]);
      continue;
    }
    span[0] = std::min(span[0], double(unit[i])), span[1] = std::min(span[1], -double(unit[i]));
  }
  comm_.minInPlace(span);  // units are below 2^40: exact in a double
  const std::int64_t u0 = span[0] == kNone ? 0 : static_cast<std::int64_t>(span[0]);
  const std::size_t units = span[0] == kNone ? 0 : static_cast<std::size_t>(-span[1] - span[0] + 1);

  // Per unit this rank's in-order keys, then its strays; summed and scanned over the ranks.
  std::vector<std::int64_t> total(units + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    ++total[unit[i] == kStray ? units : static_cast<std::size_t>(unit[i] - u0)];
  std::vector<std::int64_t> first = total;  // becomes: this rank's first place in each unit
  comm_.sumInPlace(total);
  comm_.exclusiveScanInPlace(first);
  std::int64_t below = 0;  // in-order keys of the units before, on every rank
  for (std::size_t u = 0; u < units; ++u) first[u] += below, below += total[u];
  const std::int64_t inOrderAll = below, straysAll = total[units];
  stats_.placesBytesReceived += sizeof(double) * span.size() + 2 * 8 * total.size();

  // The strays of every rank in key order, and per stray the in-order keys below it everywhere.
  std::vector<std::uint64_t> strays;
  std::vector<std::int64_t> inOrderBelow;
  if (straysAll > 0) {
    Bytes mine(myStrays.size() * sizeof(std::uint64_t));
    if (!mine.empty()) std::memcpy(mine.data(), myStrays.data(), mine.size());
    for (const Bytes& b : comm_.allGather(mine)) {
      const std::size_t at = strays.size();
      strays.resize(at + b.size() / sizeof(std::uint64_t));
      if (!b.empty()) std::memcpy(strays.data() + at, b.data(), b.size());
    }
    std::sort(strays.begin(), strays.end());
    stats_.placesStrays += strays.size();
    stats_.placesBytesReceived += 8 * (strays.size() - myStrays.size());
    if (inOrderAll > 0) {
      inOrderBelow.resize(strays.size());
      std::size_t k = 0;       // into order
      std::int64_t count = 0;  // this rank's in-order keys before order[k]
      for (std::size_t j = 0; j < strays.size(); ++j) {
        for (; k < n && keys_[order[k]] < strays[j]; ++k) count += unit[order[k]] != kStray;
        inOrderBelow[j] = count;
      }
      comm_.sumInPlace(inOrderBelow);
      stats_.placesBytesReceived += 8 * inOrderBelow.size();
    }
  }

  std::vector<std::uint64_t> places(n, 0);
  std::size_t straysBelow = 0;  // of every rank, below the current key
  std::int64_t current = kStray, inUnit = 0;
  for (std::uint32_t i : order) {
    const std::uint64_t key = keys_[i];
    while (straysBelow < strays.size() && strays[straysBelow] < key) ++straysBelow;
    if (unit[i] == kStray) {
      const std::int64_t inOrderBefore = inOrderBelow.empty() ? 0 : inOrderBelow[straysBelow];
      places[i] = static_cast<std::uint64_t>(inOrderBefore) + straysBelow;
      continue;
    }
    if (unit[i] != current) current = unit[i], inUnit = 0;
    places[i] = static_cast<std::uint64_t>(first[static_cast<std::size_t>(current - u0)] + inUnit) +
                straysBelow;
    ++inUnit;
  }
  stats_.placesCalls += 1;
  stats_.placesSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return places;
}

}  // namespace sph::dist
