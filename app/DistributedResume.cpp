#include "app/DistributedResume.h"

#include <algorithm>
#include <limits>
#include <tuple>

#include "sim/NeighbourGrid.h"

namespace sph::app {
namespace {

// Positions are read in chunks of this many particles (12 MB of x, y and z).
constexpr std::uint64_t kChunk = std::uint64_t(1) << 20;

// Calls visit(first, particles) for the chunks of the frame's particles [from, to), each with
// the arrays of `fields` (of x, y, z: cache::Field) read; from the resume record, with every
// array, when the frame does not hold the positions (output.fields without them).
template <class Visit>
void chunks(const io::CacheReader& reader, std::size_t frame, const io::cache::FieldSet& fields,
            std::uint64_t from, std::uint64_t to, Visit&& visit) {
  const bool inFrame = (reader.summary().fields & fields) == fields;
  for (std::uint64_t first = from; first < to; first += kChunk) {
    const io::h5::Runs run{{first, std::min(kChunk, to - first)}};
    visit(first,
          inFrame ? reader.readFrame(frame, fields, &run) : reader.readRestart(frame, &run).second);
  }
}

const std::vector<float>& coordinate(const Particles& p, int axis) {
  return axis == 0 ? p.x : axis == 1 ? p.y : p.z;
}

}  // namespace

ResumePart readResumePart(dist::Halo& halo, const io::CacheReader& reader, std::size_t frame,
                          float h) {
  dist::Communicator& comm = halo.comm();
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
  io::h5::Runs runs;
  if (n > 0) {
    // 2. The cut the first exchange will make: its cell size and histogram of cell planes.
    const float blo[3] = {float(lo[0]), float(lo[1]), float(lo[2])};
    const float bhi[3] = {float(hi[0]), float(hi[1]), float(hi[2])};
    const float cellSize = NeighbourGrid::cellSizeFor(blo, bhi, n, h);
    const double inv = 1.0 / static_cast<double>(cellSize);
    const long long p0 = dist::planeOf(blo[axis], inv), p1 = dist::planeOf(bhi[axis], inv);
    std::vector<std::int64_t> counts(static_cast<std::size_t>(p1 - p0 + 1), 0);
    chunks(reader, frame, along, from, to, [&](std::uint64_t, const Particles& p) {
      for (float v : coordinate(p, axis))
        ++counts[static_cast<std::size_t>(dist::planeOf(v, inv) - p0)];
    });
    comm.sumInPlace(counts);
    const dist::Slabs slabs = dist::Slabs::balance(axis, ranks, p0, counts);
    halo.startWith(slabs, cellSize);

    // 3. The runs of this rank's particles.
    chunks(reader, frame, along, 0, n, [&](std::uint64_t first, const Particles& p) {
      const std::vector<float>& c = coordinate(p, axis);
      for (std::size_t i = 0; i < c.size(); ++i) {
        if (slabs.ownerOf(dist::planeOf(c[i], inv)) != me) continue;
        const std::uint64_t index = first + i;
        if (!runs.empty() && runs.back().first + runs.back().second == index)
          ++runs.back().second;
        else
          runs.emplace_back(index, 1);
      }
    });
  }

  // 4. Their values, and the run's state.
  ResumePart part;
  std::tie(part.state, part.fluid) = reader.readRestart(frame, &runs);
  for (const auto& [first, count] : runs)
    for (std::uint64_t i = 0; i < count; ++i) part.keys.push_back(first + i);
  return part;
}

}  // namespace sph::app
