// Halo::globalPlaces: each owned particle's index in the single-process order (the order of the
// keys, docs/scaling.md "What is bit-identical"), without gathering the keys anywhere.
//
// A key made by sorted() names its cell of the key lattice, row-major (x fastest). Call a "unit"
// the cells that share the coordinates above the slab axis: a row of cells along x when the slabs
// cut x, a z plane when they cut y, the whole lattice when they cut z. A unit's cells are
// consecutive keys ordered first by the slab axis, and the slabs of the cut sorted() keyed with
// are whole planes in rank order, so within a unit every key whose cell lies in rank r's slab is
// below every key whose cell lies in rank r + 1's. Let each cell key be counted by that rank, its
// "keyer" (the rank that holds it, unless it migrated since the sort: then it is sent to its
// keyer and its place sent back). For a key keyed by rank r in unit u therefore
//   place = (cell keys of the units below u, all ranks) + (cell keys of u keyed below r)
//           + (its index among rank r's keys of u),
// which one sum and one exclusive scan over the ranks of a counter per unit give.
//
// The other keys come after every cell key: those of particles emitted since the sort
// (kEmitted | id, in id order), or, before the first sort (the particle model never sorts),
// the starting order's indices and the emitted ones after them. Laid end to end they are nearly
// dense (lost particles leave gaps), so each goes to the rank owning its share of that range, which
// sorts what it receives and places it after the shares of the ranks below (one more exclusive
// scan), and sends the places back. A rank receives the keys of its share (about even shares; the
// gaps only make them less even) and its own keys' places; nothing is all-gathered.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <limits>
#include <numeric>

#include "sim/Assert.h"
#include "sim/ranks/Halo.h"

namespace sph::ranks {
namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

Bytes packed(const std::vector<std::uint64_t>& values) {
  Bytes b(values.size() * sizeof(std::uint64_t));
  if (!b.empty()) std::memcpy(b.data(), values.data(), b.size());
  return b;
}

std::vector<std::uint64_t> unpacked(const Bytes& b) {
  std::vector<std::uint64_t> v(b.size() / sizeof(std::uint64_t));
  if (!v.empty()) std::memcpy(v.data(), b.data(), b.size());
  return v;
}

// Sends values[r] to rank r; returns what each rank sent here (adds what came from the others
// to bytesReceived).
std::vector<std::vector<std::uint64_t>> exchanged(
    Communicator& comm, const std::vector<std::vector<std::uint64_t>>& values,
    std::uint64_t& bytesReceived) {
  std::vector<Bytes> send(values.size());
  for (std::size_t r = 0; r < values.size(); ++r) send[r] = packed(values[r]);
  const std::vector<Bytes> received = comm.allToAll(send);
  std::vector<std::vector<std::uint64_t>> out;
  for (std::size_t r = 0; r < received.size(); ++r) {
    if (static_cast<int>(r) != comm.rank()) bytesReceived += received[r].size();
    out.push_back(unpacked(received[r]));
  }
  return out;
}

// The places of this rank's `values` among every rank's, from `offset` on, in the order given:
// the values (distinct over the ranks, each below `range`) go to the rank owning their share of
// [0, range), which sorts what it receives and counts from the shares of the ranks below it.
std::vector<std::uint64_t> placesByShares(Communicator& comm,
                                          const std::vector<std::uint64_t>& values,
                                          std::uint64_t range, std::uint64_t offset,
                                          std::uint64_t& bytesReceived) {
  const int ranks = comm.size();
  // values < 2^33 (indices and ids are 32-bit), so value * ranks stays far below 2^64.
  const auto shareOf = [&](std::uint64_t v) {
    return static_cast<int>(v * static_cast<std::uint64_t>(ranks) / range);
  };
  std::vector<std::vector<std::uint64_t>> sent(ranks);
  for (std::uint64_t v : values) sent[shareOf(v)].push_back(v);
  const auto share = exchanged(comm, sent, bytesReceived);
  std::vector<std::uint64_t> mine;  // this rank's share, in order
  for (const auto& s : share) mine.insert(mine.end(), s.begin(), s.end());
  std::sort(mine.begin(), mine.end());
  std::vector<std::int64_t> below{static_cast<std::int64_t>(mine.size())};
  comm.exclusiveScanInPlace(below);
  bytesReceived += sizeof below[0];
  const std::uint64_t from = offset + static_cast<std::uint64_t>(below[0]);
  std::vector<std::vector<std::uint64_t>> answers(ranks);
  for (int r = 0; r < ranks; ++r)
    for (std::uint64_t v : share[r])
      answers[r].push_back(
          from +
          static_cast<std::uint64_t>(std::lower_bound(mine.begin(), mine.end(), v) - mine.begin()));
  const auto answered = exchanged(comm, answers, bytesReceived);
  std::vector<std::size_t> next(ranks, 0);
  std::vector<std::uint64_t> places;
  places.reserve(values.size());
  for (std::uint64_t v : values) {
    const int r = shareOf(v);
    places.push_back(answered[r][next[r]++]);
  }
  return places;
}

}  // namespace

std::vector<std::uint64_t> Halo::globalPlaces() {
  SPH_ASSERT(ghost_.empty());
  // Before the first exchange (frame 0 of a distributed start or of a resume) a key is the
  // particle's index in the starting order, laid out 0 .. N - 1 over the ranks: its place.
  if (startOrder_) {
    stats_.placesCalls += 1;
    return keys_;
  }
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = keys_.size();
  const int me = rank(), ranksCount = ranks();
  std::uint64_t& bytes = stats_.placesBytesReceived;

  // Each key's unit and keyer (cell keys), or -1 for the keys after every cell key.
  std::vector<std::int64_t> unit(n, -1);
  std::vector<int> keyer(n, -1);
  const int axis = keyedSlabs_.axis;
  const long long d0 = keyedLattice_.dims[0], d1 = keyedLattice_.dims[1];
  long long lastLinear = -1;  // a cell's keys come together: decode each cell once
  std::int64_t lastUnit = 0;
  int lastKeyer = 0;
  // The span of the units, and of the two kinds of other keys (minus the maxima, for one min).
  std::vector<double> span(7, kNone);  // unit, -unit, start, -start, id, -id, -(cell key to send)
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t key = keys_[i];
    if (key & kEmitted) {
      const double id = double(key & ~kEmitted);
      span[4] = std::min(span[4], id), span[5] = std::min(span[5], -id);
      continue;
    }
    if (!keyed_) {
      span[2] = std::min(span[2], double(key)), span[3] = std::min(span[3], -double(key));
      continue;
    }
    const auto linear = static_cast<long long>(key >> kWithinBits);
    if (linear != lastLinear) {
      const long long c[3] = {linear % d0, linear / d0 % d1, linear / d0 / d1};
      lastLinear = linear;
      lastUnit = axis == 0 ? linear / d0 : axis == 1 ? c[2] : 0;
      lastKeyer = keyedSlabs_.ownerOf(c[axis] + keyedLattice_.origin[axis]);
    }
    unit[i] = lastUnit, keyer[i] = lastKeyer;
    span[0] = std::min(span[0], double(lastUnit)), span[1] = std::min(span[1], -double(lastUnit));
    if (lastKeyer != me) span[6] = -1;
  }
  comm_.minInPlace(span);  // units, indices and ids are below 2^53: exact in a double
  bytes += sizeof(double) * span.size();

  // Cell keys that migrated since the sort go to their keyer, in key order.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  if (!std::is_sorted(keys_.begin(), keys_.end()))
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return keys_[a] < keys_[b]; });
  std::vector<std::vector<std::uint64_t>> away(ranksCount), arrived(ranksCount);
  for (std::uint32_t i : order)
    if (keyer[i] >= 0 && keyer[i] != me) away[keyer[i]].push_back(keys_[i]);
  if (span[6] < 0) {
    arrived = exchanged(comm_, away, bytes);
    for (const auto& a : away) stats_.placesStrays += a.size();
  }

  // The keys that arrived, in key order, with where their places go (rank, index).
  struct Arrival {
    std::uint64_t key;
    std::uint32_t from, index;
  };
  std::vector<Arrival> arrivals;
  for (int r = 0; r < ranksCount; ++r)
    for (std::size_t j = 0; j < arrived[r].size(); ++j)
      arrivals.push_back({arrived[r][j], std::uint32_t(r), std::uint32_t(j)});
  std::sort(arrivals.begin(), arrivals.end(),
            [](const Arrival& x, const Arrival& y) { return x.key < y.key; });
  const long long dims01 = d0 * d1;
  const auto unitOf = [&](std::uint64_t key) -> std::int64_t {
    const auto linear = static_cast<long long>(key >> kWithinBits);
    return axis == 0 ? linear / d0 : axis == 1 ? linear / dims01 : 0;
  };
  // Visits the cell keys this rank keys in key order: its own (local index, from = -1), merged
  // with the arrivals (from = the sender).
  const auto forEachKeyed = [&](auto&& visit) {
    std::size_t a = 0;
    for (std::uint32_t i : order) {
      if (keyer[i] != me) continue;
      for (; a < arrivals.size() && arrivals[a].key < keys_[i]; ++a)
        visit(arrivals[a].key, unitOf(arrivals[a].key), int(arrivals[a].from), arrivals[a].index);
      visit(keys_[i], unit[i], -1, i);
    }
    for (; a < arrivals.size(); ++a)
      visit(arrivals[a].key, unitOf(arrivals[a].key), int(arrivals[a].from), arrivals[a].index);
  };

  // Per unit the keys this rank keys, summed and scanned over the ranks.
  const std::int64_t u0 = span[0] == kNone ? 0 : static_cast<std::int64_t>(span[0]);
  const std::size_t units = span[0] == kNone ? 0 : static_cast<std::size_t>(-span[1] - span[0] + 1);
  std::vector<std::int64_t> total(units, 0);
  forEachKeyed([&](std::uint64_t, std::int64_t u, int, std::uint32_t) {
    ++total[static_cast<std::size_t>(u - u0)];
  });
  std::vector<std::int64_t> first = total;  // becomes: this rank's first place in each unit
  if (units > 0) {
    comm_.sumInPlace(total);
    comm_.exclusiveScanInPlace(first);
    bytes += 2 * 8 * units;
  }
  std::int64_t cellKeys = 0;  // of the units before, on every rank
  for (std::size_t u = 0; u < units; ++u) first[u] += cellKeys, cellKeys += total[u];

  std::vector<std::uint64_t> places(n, 0);
  std::vector<std::vector<std::uint64_t>> back(ranksCount);
  for (int r = 0; r < ranksCount; ++r) back[r].resize(arrived[r].size());
  std::int64_t current = -1, inUnit = 0;
  forEachKeyed([&](std::uint64_t, std::int64_t u, int from, std::uint32_t index) {
    if (u != current) current = u, inUnit = 0;
    const auto place =
        static_cast<std::uint64_t>(first[static_cast<std::size_t>(u - u0)] + inUnit++);
    (from < 0 ? places[index] : back[from][index]) = place;
  });
  if (span[6] < 0) {
    const auto returned = exchanged(comm_, back, bytes);
    std::vector<std::size_t> next(ranksCount, 0);  // in the order `away` was filled
    for (std::uint32_t i : order)
      if (keyer[i] >= 0 && keyer[i] != me) places[i] = returned[keyer[i]][next[keyer[i]]++];
  }

  // The other keys: the starting order's indices, then the emitted ids, laid end to end (each
  // kind's order is its keys'), cut into equal shares of that range, one a rank.
  const bool starts = span[2] != kNone, emitted = span[4] != kNone;
  if (starts || emitted) {
    const std::uint64_t startLo = starts ? std::uint64_t(span[2]) : 0;
    const std::uint64_t startCount = starts ? std::uint64_t(-span[3]) - startLo + 1 : 0;
    const std::uint64_t idLo = emitted ? std::uint64_t(span[4]) : 0;
    const std::uint64_t range = startCount + (emitted ? std::uint64_t(-span[5]) - idLo + 1 : 0);
    const auto dense = [&](std::uint64_t key) {
      return key & kEmitted ? startCount + ((key & ~kEmitted) - idLo) : key - startLo;
    };
    std::vector<std::uint64_t> values;
    for (std::uint32_t i : order)
      if (keyer[i] < 0) values.push_back(dense(keys_[i]));
    stats_.placesStrays += values.size();
    const std::vector<std::uint64_t> placed =
        placesByShares(comm_, values, range, static_cast<std::uint64_t>(cellKeys), bytes);
    std::size_t k = 0;
    for (std::uint32_t i : order)
      if (keyer[i] < 0) places[i] = placed[k++];
  }
  stats_.placesCalls += 1;
  stats_.placesSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return places;
}

}  // namespace sph::ranks
