#include "job/distributed/DistributedResume.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <tuple>

#include "sim/grid/NeighbourGrid.h"

namespace sph::job::distributed {
namespace {

// Positions are read in chunks of this many particles (12 MB of x, y and z).
constexpr std::uint64_t kChunk = std::uint64_t(1) << 20;

// Calls visit(first, particles) for the chunks of the frame's particles [from, to), each with
// the arrays of `fields` (of x, y, z: cache::Field) read; from the resume record, with every
// array, when the frame does not hold the positions (output.fields without them).
template <class Visit>
void chunks(const io::cache::CacheReader& reader, std::size_t frame,
            const io::cache::FieldSet& fields, std::uint64_t from, std::uint64_t to,
            Visit&& visit) {
  const bool inFrame = (reader.summary().fields & fields) == fields;
  for (std::uint64_t first = from; first < to; first += kChunk) {
    const io::cache::h5::Runs run{{first, std::min(kChunk, to - first)}};
    visit(first,
          inFrame ? reader.readFrame(frame, fields, &run) : reader.readRestart(frame, &run).second);
  }
}

const std::vector<float>& coordinate(const Particles& p, int axis) {
  return axis == 0 ? p.x : axis == 1 ? p.y : p.z;
}

// Appends the indices [first, first + count) to `runs` (ascending), joining a run it continues.
void addToRuns(io::cache::h5::Runs& runs, std::uint64_t first, std::uint64_t count) {
  if (!runs.empty() && runs.back().first + runs.back().second == first)
    runs.back().second += count;
  else
    runs.emplace_back(first, count);
}

ranks::Bytes toBytes(const io::cache::h5::Runs& runs) {
  ranks::Bytes b(runs.size() * 2 * sizeof(std::uint64_t));
  std::size_t at = 0;
  for (const auto& [first, count] : runs) {
    std::memcpy(b.data() + at, &first, sizeof first), at += sizeof first;
    std::memcpy(b.data() + at, &count, sizeof count), at += sizeof count;
  }
  return b;
}

io::cache::h5::Runs fromBytes(const ranks::Bytes& b) {
  io::cache::h5::Runs runs(b.size() / (2 * sizeof(std::uint64_t)));
  std::size_t at = 0;
  for (auto& [first, count] : runs) {
    std::memcpy(&first, b.data() + at, sizeof first), at += sizeof first;
    std::memcpy(&count, b.data() + at, sizeof count), at += sizeof count;
  }
  return runs;
}

}  // namespace

ResumePart readResumePart(ranks::Halo& halo, const io::cache::CacheReader& reader,
                          std::size_t frame, float h) {
  ranks::Communicator& comm = halo.comm();
  const int ranks = comm.size(), me = comm.rank(), axis = halo.slabs().axis;
  const std::uint64_t n = reader.summary().frames.at(frame).particles;
  const std::uint64_t from = n * me / ranks, to = n * (me + 1) / ranks;  // this rank's share
  io::cache::FieldSet xyz, along;
  for (int a = 0; a < 3; ++a) xyz.set(a);  // Field::X, Y, Z
  along.set(axis);

  // 1. The bounding box of every particle (the cell size depends on it).
  std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -lo[0]);
  chunks(reader, frame, xyz, from, to, [&](std::uint64_t, const Particles& p) {
    for (int a = 0; a < 3; ++a)
      for (float v : coordinate(p, a))
        lo[a] = std::min(lo[a], double(v)), hi[a] = std::max(hi[a], double(v));
  });
  comm.minInPlace(lo);
  comm.maxInPlace(hi);
  io::cache::h5::Runs runs;
  if (n > 0) {
    // 2. The cut the first exchange will make: its cell size and histogram of cell planes.
    const float blo[3] = {float(lo[0]), float(lo[1]), float(lo[2])};
    const float bhi[3] = {float(hi[0]), float(hi[1]), float(hi[2])};
    const float cellSize = grid::NeighbourGrid::cellSizeFor(blo, bhi, n, h);
    const double inv = 1.0 / static_cast<double>(cellSize);
    const long long p0 = ranks::planeOf(blo[axis], inv), p1 = ranks::planeOf(bhi[axis], inv);
    std::vector<std::int64_t> counts(static_cast<std::size_t>(p1 - p0 + 1), 0);
    std::vector<float> share;  // the slab-axis coordinate of this rank's share, kept for step 3
    share.reserve(to - from);
    chunks(reader, frame, along, from, to, [&](std::uint64_t, const Particles& p) {
      for (float v : coordinate(p, axis))
        ++counts[static_cast<std::size_t>(ranks::planeOf(v, inv) - p0)], share.push_back(v);
    });
    comm.sumInPlace(counts);
    const ranks::Slabs slabs = ranks::Slabs::balance(axis, ranks, p0, counts);
    halo.startWith(slabs, cellSize);

    // 3. The runs of this rank's particles: each rank finds, in its share, the runs of indices
    // of every rank's slab and sends them to that rank (16 bytes a run: the frame is in key
    // order, grid cell by grid cell, so runs are far fewer than particles); a rank receives its
    // runs in the shares' order, ascending. No rank reads more than its share of coordinates.
    std::vector<io::cache::h5::Runs> found(static_cast<std::size_t>(ranks));
    for (std::size_t i = 0; i < share.size(); ++i) {
      io::cache::h5::Runs& r =
          found[static_cast<std::size_t>(slabs.ownerOf(ranks::planeOf(share[i], inv)))];
      addToRuns(r, from + i, 1);
    }
    std::vector<ranks::Bytes> send(static_cast<std::size_t>(ranks));
    for (int r = 0; r < ranks; ++r)
      send[static_cast<std::size_t>(r)] = toBytes(found[static_cast<std::size_t>(r)]);
    for (const ranks::Bytes& b : comm.allToAll(send))
      for (const auto& [first, count] : fromBytes(b)) addToRuns(runs, first, count);
  }

  // 4. Their values, and the run's state.
  ResumePart part;
  std::tie(part.state, part.fluid) = reader.readRestart(frame, &runs);
  for (const auto& [first, count] : runs)
    for (std::uint64_t i = 0; i < count; ++i) part.keys.push_back(first + i);
  return part;
}

}  // namespace sph::job::distributed
