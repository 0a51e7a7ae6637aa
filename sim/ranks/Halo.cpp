#include "sim/ranks/Halo.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include "sim/Assert.h"
#include "sim/Parallel.h"

namespace sph::ranks {
namespace {

constexpr long long kFar = 1LL << 60;

const std::vector<float>& axisOf(const Particles& f, int axis) {
  return axis == 0 ? f.x : axis == 1 ? f.y : f.z;
}

using Attached = std::vector<std::vector<float>*>;

// A particle's record: its 13 fields, its attached values, its key.
std::size_t recordBytes(const Attached& attached) {
  return Particles::kFieldCount * 4 + attached.size() * 4 + 8;
}

void pack(const Particles& f, std::size_t i, std::uint64_t key, const Attached& attached,
          Bytes& out) {
  const std::size_t at = out.size();
  out.resize(at + recordBytes(attached));
  std::uint8_t* p = out.data() + at;
  f.forEachField([&](const auto& field) {
    std::memcpy(p, &field[i], 4);
    p += 4;
  });
  for (const std::vector<float>* a : attached) {
    std::memcpy(p, &(*a)[i], 4);
    p += 4;
  }
  std::memcpy(p, &key, 8);
}

// Appends the records of `in` to f, their attached values to `attached` and their keys to keys.
void unpack(const Bytes& in, Particles& f, std::vector<std::uint64_t>& keys,
            const Attached& attached) {
  const std::size_t bytes = recordBytes(attached);
  const std::size_t count = in.size() / bytes, base = f.size();
  f.resize(base + count);
  keys.resize(base + count);
  for (std::vector<float>* a : attached) a->resize(base + count);
  for (std::size_t r = 0; r < count; ++r) {
    const std::uint8_t* p = in.data() + r * bytes;
    f.forEachField([&](auto& field) {
      std::memcpy(&field[base + r], p, 4);
      p += 4;
    });
    for (std::vector<float>* a : attached) {
      std::memcpy(&(*a)[base + r], p, 4);
      p += 4;
    }
    std::memcpy(&keys[base + r], p, 8);
  }
}

// Keeps the particles with keep[i] != 0, in order.
void compact(Particles& f, std::vector<std::uint64_t>& keys, const Attached& attached,
             const std::vector<std::uint8_t>& keep) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i]) continue;
    if (n != i) {
      f.forEachField([&](auto& field) { field[n] = field[i]; });
      for (std::vector<float>* a : attached) (*a)[n] = (*a)[i];
      keys[n] = keys[i];
    }
    ++n;
  }
  f.resize(n);
  keys.resize(n);
  for (std::vector<float>* a : attached) a->resize(n);
}

template <class T>
void permuteVector(std::vector<T>& v, const std::vector<std::uint32_t>& order) {
  std::vector<T> out(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) out[i] = v[order[i]];
  v.swap(out);
}

}  // namespace

int Slabs::ownerOf(long long plane) const {
  // The number of inner cuts at or below the plane.
  const auto begin = first.begin() + 1, end = first.end() - 1;
  return static_cast<int>(std::upper_bound(begin, end, plane) - begin);
}

Slabs Slabs::balance(int axis, int ranks, long long firstPlane,
                     const std::vector<std::int64_t>& counts) {
  Slabs s;
  s.axis = axis;
  s.first.assign(ranks + 1, 0);
  s.first.front() = -kFar;
  s.first.back() = kFar;
  const std::int64_t total = std::accumulate(counts.begin(), counts.end(), std::int64_t(0));
  const long long planes = static_cast<long long>(counts.size());
  std::size_t i = 0;
  std::int64_t below = 0;  // particles in the planes before i
  for (int r = 1; r < ranks; ++r) {
    if (total == 0) {
      s.first[r] = firstPlane + planes * r / ranks;
      continue;
    }
    // The first plane with at least r/ranks of the particles below it.
    while (i < counts.size() && below * ranks < total * r) below += counts[i++];
    s.first[r] = firstPlane + static_cast<long long>(i);
  }
  return s;
}

Halo::Halo(Communicator& comm, const Aabb& domain, float h) : comm_(comm), domain_(domain) {
  const Vec3 extent = domain.hi - domain.lo;
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (extent[a] > extent[axis]) axis = a;
  // Until the first exchange counts the particles: equal slices of the domain.
  cellSize_ = h;
  const double inv = 1.0 / static_cast<double>(h);
  const long long p0 = planeOf(domain.lo[axis], inv), p1 = planeOf(domain.hi[axis], inv);
  slabs_ = Slabs::balance(axis, comm.size(), p0, std::vector<std::int64_t>(p1 - p0 + 1, 0));
}

void Halo::adopt(const Particles& fluid, std::vector<std::uint64_t> keys) {
  if (keys.empty()) {
    keys.resize(fluid.size());
    std::iota(keys.begin(), keys.end(), std::uint64_t(0));
  }
  SPH_ASSERT(keys.size() == fluid.size());
  keys_.swap(keys);
  keyed_ = false;
  startOrder_ = true;
  ghost_.clear();
}

void Halo::startWith(const Slabs& slabs, float cellSize) {
  SPH_ASSERT(slabs.axis == slabs_.axis && slabs.ranks() == ranks());
  slabs_ = slabs;
  cellSize_ = cellSize;
}

void Halo::attach(std::vector<float>& field) {
  attached_.push_back(&field);  // exchange() sizes it: until then it may be empty, as alone
}

bool Halo::owns(const Vec3& p) const {
  const double inv = 1.0 / static_cast<double>(cellSize_);
  return slabs_.ownerOf(planeOf(p[slabs_.axis], inv)) == rank();
}

float Halo::exchange(Particles& f, float h) {
  const auto start = std::chrono::steady_clock::now();
  const int ranksCount = ranks(), me = rank(), axis = slabs_.axis;
  startOrder_ = false;
  for (std::size_t i = keys_.size(); i < f.size(); ++i) keys_.push_back(kEmitted | f.id[i]);
  for (std::vector<float>* a : attached_) a->resize(f.size(), 0.0f);  // as sortParticles() does
  ghost_.clear();

  // The grid every rank builds has the cell size the single process's grid would choose: from
  // the bounding box and the number of all particles.
  std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -lo[0]);
  for (int a = 0; a < 3; ++a) {
    const std::vector<float>& c = axisOf(f, a);
    for (float v : c) lo[a] = std::min(lo[a], double(v)), hi[a] = std::max(hi[a], double(v));
  }
  comm_.minInPlace(lo);
  comm_.maxInPlace(hi);
  const std::uint64_t total = globalCount(f.size());
  if (total == 0) return cellSize_ = h;
  const float blo[3] = {float(lo[0]), float(lo[1]), float(lo[2])};
  const float bhi[3] = {float(hi[0]), float(hi[1]), float(hi[2])};
  const float cs = grid::NeighbourGrid::cellSizeFor(blo, bhi, total, h);
  const double inv = 1.0 / static_cast<double>(cs);

  // Re-cut the slabs: equal particle counts.
  const long long p0 = planeOf(blo[axis], inv), p1 = planeOf(bhi[axis], inv);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(p1 - p0 + 1), 0);
  const std::vector<float>& along = axisOf(f, axis);
  for (float v : along) ++counts[static_cast<std::size_t>(planeOf(v, inv) - p0)];
  // The previous exchange's migrations (none counted for the first, which moves none: each rank
  // starts or resumes with its own slab) ride along.
  counts.push_back(stats_.steps > 1 ? static_cast<std::int64_t>(migratedLast_) : 0);
  comm_.sumInPlace(counts);
  stats_.migratedAllRanks += static_cast<std::uint64_t>(counts.back());
  counts.pop_back();
  slabs_ = Slabs::balance(axis, ranksCount, p0, counts);
  std::int64_t most = 0;
  for (int r = 0; r < ranksCount; ++r) {
    std::int64_t n = 0;
    for (long long p = std::max(p0, slabs_.first[r]); p < std::min(p1 + 1, slabs_.first[r + 1]);
         ++p)
      n += counts[static_cast<std::size_t>(p - p0)];
    most = std::max(most, n);
  }
  const double imbalance = double(most) * ranksCount / double(total);
  stats_.imbalanceSum += imbalance;
  stats_.imbalanceMax = std::max(stats_.imbalanceMax, imbalance);

  // Migration: particles outside this rank's slab go to their owner.
  std::vector<Bytes> send(ranksCount);
  std::vector<std::uint8_t> keep(f.size(), 1);
  migratedLast_ = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const int owner = slabs_.ownerOf(planeOf(along[i], inv));
    if (owner == me) continue;
    pack(f, i, keys_[i], attached_, send[owner]);
    keep[i] = 0;
    ++migratedLast_;
  }
  stats_.migrated += migratedLast_;
  for (const Bytes& b : send) stats_.bytesSent += b.size();
  compact(f, keys_, attached_, keep);
  // What stayed is in key order: last step's sorted owned particles, then the emitted ones
  // (keys above every cell's, in id order).
  const std::size_t stayed = f.size();
  for (const Bytes& b : comm_.allToAll(send)) unpack(b, f, keys_, attached_);
  const std::size_t owned = f.size();

  // Ghosts: the owned particles within kGhostPlanes planes of another rank's slab. The lists of
  // who went where stay for refreshGhosts().
  for (Bytes& b : send) b.clear();
  sentTo_.assign(ranksCount, {});
  receivedFrom_.assign(ranksCount, {});
  for (std::size_t i = 0; i < owned; ++i) {
    const long long p = planeOf(along[i], inv);
    for (int r = 0; r < ranksCount; ++r) {
      if (r == me) continue;
      if (p >= slabs_.first[r] - kGhostPlanes && p < slabs_.first[r + 1] + kGhostPlanes) {
        pack(f, i, keys_[i], attached_, send[r]);
        sentTo_[r].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
  for (const Bytes& b : send) stats_.bytesSent += b.size();
  const std::vector<Bytes> ghosts = comm_.allToAll(send);
  for (int r = 0; r < ranksCount; ++r) {
    const std::size_t from = f.size();
    unpack(ghosts[r], f, keys_, attached_);
    for (std::size_t i = from; i < f.size(); ++i)
      receivedFrom_[r].push_back(static_cast<std::uint32_t>(i));
  }
  ghost_.assign(f.size(), 1);
  std::fill(ghost_.begin(), ghost_.begin() + static_cast<std::ptrdiff_t>(owned), 0);
  stats_.ghostsReceived += f.size() - owned;

  // The global order restricted to the particles here: the grid's stable sort then reproduces
  // the single process's order.
  // the particles that stayed are in order already: sort the arrivals and merge.
  order_.resize(f.size());
  std::iota(order_.begin(), order_.end(), 0u);
  const auto byKey = [&](std::uint32_t a, std::uint32_t b) { return keys_[a] < keys_[b]; };
  const auto arrivals = order_.begin() + static_cast<std::ptrdiff_t>(stayed);
  std::sort(arrivals, order_.end(), byKey);
  std::inplace_merge(order_.begin(), arrivals, order_.end(), byKey);
  std::vector<std::uint32_t> scratch;
  f.permute(order_, scratch);
  permuted(order_);
  cellSize_ = cs;
  stats_.steps += 1;
  stats_.exchangeSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cs;
}

Halo::KeyLattice Halo::keyLattice() const {
  const double inv = 1.0 / static_cast<double>(cellSize_);
  KeyLattice l;
  for (int a = 0; a < 3; ++a) {
    l.origin[a] = planeOf(domain_.lo[a], inv) - kGhostPlanes;
    l.dims[a] = planeOf(domain_.hi[a], inv) + kGhostPlanes - l.origin[a] + 1;
  }
  return l;
}

std::uint64_t Halo::globalKey(const KeyLattice& l, const grid::CellCoord& cell,
                              std::uint32_t within) {
  long long c[3];
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(cell[a] - l.origin[a], 0LL, l.dims[a] - 1);
  const std::uint64_t linear =
      static_cast<std::uint64_t>((c[2] * l.dims[1] + c[1]) * l.dims[0] + c[0]);
  SPH_ASSERT(within < (1u << kWithinBits));
  return (linear << kWithinBits) | within;
}

void Halo::permuted(const std::vector<std::uint32_t>& order) {
  permuteVector(keys_, order);
  permuteVector(ghost_, order);
  for (std::vector<float>* a : attached_) permuteVector(*a, order);
  // The particle at old index order[i] is now at i.
  std::vector<std::uint32_t> to(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) to[order[i]] = static_cast<std::uint32_t>(i);
  for (auto* lists : {&sentTo_, &receivedFrom_})
    for (std::vector<std::uint32_t>& list : *lists)
      for (std::uint32_t& i : list) i = to[i];
}

void Halo::sorted(const grid::NeighbourGrid& grid, const std::vector<std::uint32_t>& order) {
  permuted(order);
  keyed_ = true;
  keyedLattice_ = keyLattice();
  keyedSlabs_ = slabs_;
  // Cells are whole planes' worth of one owner: an owned particle's cell holds only owned ones.
  parallelFor(grid.cellCount(), [&](std::size_t cell) {
    const std::uint32_t begin = grid.cellBegin(cell), end = grid.cellEnd(cell);
    if (begin == end || ghost_[begin]) return;
    const grid::CellCoord g = grid.globalOf(cell);
    for (std::uint32_t s = begin; s < end; ++s) keys_[s] = globalKey(keyedLattice_, g, s - begin);
  });
}

void Halo::refreshGhosts(std::initializer_list<std::vector<float>*> fields) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t bytes = 4 * fields.size();
  std::vector<Bytes> send(sentTo_.size());
  for (std::size_t r = 0; r < sentTo_.size(); ++r) {
    send[r].resize(sentTo_[r].size() * bytes);
    std::uint8_t* p = send[r].data();
    for (std::uint32_t i : sentTo_[r])
      for (const std::vector<float>* field : fields) {
        std::memcpy(p, &(*field)[i], 4);
        p += 4;
      }
    stats_.refreshBytesSent += send[r].size();
  }
  const std::vector<Bytes> received = comm_.allToAll(send);
  for (std::size_t r = 0; r < receivedFrom_.size(); ++r) {
    SPH_ASSERT(received[r].size() == receivedFrom_[r].size() * bytes);
    const std::uint8_t* p = received[r].data();
    for (std::uint32_t i : receivedFrom_[r])
      for (std::vector<float>* field : fields) {
        std::memcpy(&(*field)[i], p, 4);
        p += 4;
      }
  }
  stats_.refreshes += 1;
  stats_.refreshSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Halo::dropGhosts(Particles& f) {
  std::vector<std::uint8_t> keep(ghost_.size());
  for (std::size_t i = 0; i < keep.size(); ++i) keep[i] = ghost_[i] ? 0 : 1;
  compact(f, keys_, attached_, keep);
  ghost_.clear();
  sentTo_.clear();
  receivedFrom_.clear();
}

void Halo::removeLocal(const std::vector<std::uint8_t>& keep) {
  if (keep.empty()) return;
  SPH_ASSERT(ghost_.empty() && keep.size() == keys_.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) keys_[n++] = keys_[i];
  keys_.resize(n);
}

std::uint64_t Halo::globalCount(std::size_t local) {
  std::vector<std::int64_t> n{static_cast<std::int64_t>(local)};
  comm_.sumInPlace(n);
  return static_cast<std::uint64_t>(n[0]);
}

Particles Halo::gather(const Particles& f, std::vector<std::vector<float>>* attached) {
  return merged(f, /*everyRank=*/false, nullptr, attached);
}

Particles Halo::allGather(const Particles& f, std::vector<std::uint32_t>& mine) {
  return merged(f, /*everyRank=*/true, &mine, nullptr);
}

Particles Halo::merged(const Particles& f, bool everyRank, std::vector<std::uint32_t>* mine,
                       std::vector<std::vector<float>>* attached) {
  SPH_ASSERT(ghost_.empty() && keys_.size() == f.size());
  // Before the first exchange the attached fields (DFSPH's warm start) are not sized yet and a
  // start has none: a gathered frame 0 carries none, as the single process's (every rank agrees).
  const Attached sent = attached && !startOrder_ ? attached_ : Attached{};
  Bytes packed;
  packed.reserve(f.size() * recordBytes(sent));
  for (std::size_t i = 0; i < f.size(); ++i) pack(f, i, keys_[i], sent, packed);
  Particles all;
  std::vector<std::uint64_t> keys;
  std::vector<std::vector<float>> values(sent.size());
  Attached into;
  for (std::vector<float>& v : values) into.push_back(&v);
  std::size_t myFirst = 0;
  const std::vector<Bytes> parts = everyRank ? comm_.allGather(packed) : comm_.gatherToRoot(packed);
  for (std::size_t r = 0; r < parts.size(); ++r) {
    if (static_cast<int>(r) == rank()) myFirst = all.size();
    unpack(parts[r], all, keys, into);
  }
  std::vector<std::uint32_t> order(all.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  if (mine) {  // where this rank's particle i went: order[j] = myFirst + i
    mine->assign(f.size(), 0);
    for (std::size_t j = 0; j < order.size(); ++j)
      if (order[j] >= myFirst && order[j] < myFirst + f.size()) (*mine)[order[j] - myFirst] = j;
  }
  std::vector<std::uint32_t> scratch;
  all.permute(order, scratch);
  if (attached) {
    for (std::vector<float>& v : values) permuteVector(v, order);
    attached->swap(values);
  }
  return all;
}

void Halo::agreeOnStability(const std::optional<StabilityError>& local) {
  Bytes mine;
  if (local) {
    const StabilityError& e = *local;
    const std::string text = e.what();
    const int kind = static_cast<int>(e.kind);
    const float v[6] = {e.position.x(), e.position.y(), e.position.z(),
                        e.velocity.x(), e.velocity.y(), e.velocity.z()};
    mine.resize(sizeof kind + sizeof e.step + sizeof e.time + sizeof e.particleId + sizeof v);
    std::uint8_t* p = mine.data();
    std::memcpy(p, &kind, sizeof kind), p += sizeof kind;
    std::memcpy(p, &e.step, sizeof e.step), p += sizeof e.step;
    std::memcpy(p, &e.time, sizeof e.time), p += sizeof e.time;
    std::memcpy(p, &e.particleId, sizeof e.particleId), p += sizeof e.particleId;
    std::memcpy(p, v, sizeof v);
    mine.insert(mine.end(), text.begin(), text.end());
  }
  const std::vector<Bytes> all = comm_.allGather(mine);
  const Bytes* first = nullptr;
  std::uint32_t firstId = 0;
  bool firstNonFinite = false;
  constexpr std::size_t kIdAt = sizeof(int) + sizeof(std::uint64_t) + sizeof(double);
  for (const Bytes& b : all) {
    if (b.empty()) continue;
    std::uint32_t id;
    int kindOf;
    std::memcpy(&id, b.data() + kIdAt, sizeof id);
    std::memcpy(&kindOf, b.data(), sizeof kindOf);
    const bool nonFinite = kindOf == static_cast<int>(StabilityError::Kind::NonFinite);
    // As checkStability() chooses among one process's particles (sim/solver/Integration.cpp).
    const bool better =
        !first || (nonFinite && !firstNonFinite) || (nonFinite == firstNonFinite && id < firstId);
    if (better) first = &b, firstId = id, firstNonFinite = nonFinite;
  }
  if (!first) return;
  int kind;
  std::uint64_t step;
  double time;
  float v[6];
  const std::uint8_t* p = first->data();
  std::memcpy(&kind, p, sizeof kind), p += sizeof kind;
  std::memcpy(&step, p, sizeof step), p += sizeof step;
  std::memcpy(&time, p, sizeof time), p += sizeof time;
  p += sizeof firstId;
  std::memcpy(v, p, sizeof v), p += sizeof v;
  const std::string text(reinterpret_cast<const char*>(p),
                         static_cast<std::size_t>(first->data() + first->size() - p));
  throw StabilityError(static_cast<StabilityError::Kind>(kind), step, time, firstId,
                       Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5]), text);
}

bool Halo::any(bool local) {
  std::vector<std::int64_t> flag{local ? 1 : 0};
  comm_.sumInPlace(flag);
  return flag[0] > 0;
}

void Halo::maxOverRanks(float& a, float& b) {
  std::vector<double> v{a, b};
  comm_.maxInPlace(v);
  a = static_cast<float>(v[0]), b = static_cast<float>(v[1]);
}

}  // namespace sph::ranks
