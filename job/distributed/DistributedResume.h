// A resume on K processes (docs/scaling.md, "A distributed resume"): each rank reads only its
// slab of the cache's last frame, so no rank holds the whole of it.
//
// The frame is in the single-process order, so a particle's index in it is its key and its place
// (as the starting order's index is at a fresh start). The cut is the one the first exchange will
// make from these particles: each rank reads an equal share of the frame's positions in chunks
// (hyperslab reads), for the bounding box (a min and a max over the ranks) and then, once the
// cell size is known from it (NeighbourGrid::cellSizeFor), for the histogram of cell planes along
// the slab axis (an integer sum). Each rank then finds, in its share's slab-axis coordinates (kept
// from the histogram), the runs of indices of every rank's slab and sends them to that rank (one
// all-to-all), and reads its runs of every array and of the resume record. Memory: a chunk, the
// share's coordinate and the rank's particles; reading: 4 N / K values of the positions and the
// rank's part of every array, a rank (before, every rank also read the whole frame's slab-axis
// coordinate to find its runs: 4 N / K + N).
#pragma once

#include <cstdint>
#include <vector>

#include "io/cache/CacheReader.h"
#include "sim/run/Simulation.h"
#include "sim/ranks/Halo.h"

namespace sph::job::distributed {

struct ResumePart {
  run::RunState state;
  Particles fluid;                  // this rank's particles of the frame, in its order
  std::vector<std::uint64_t> keys;  // their indices in the frame
};

// Collective. Sets `halo`'s first cut (Halo::startWith) and returns this rank's part of frame
// `frame` of `reader`'s cache (its resume record). `h`: the support radius.
ResumePart readResumePart(ranks::Halo& halo, const io::cache::CacheReader& reader,
                          std::size_t frame, float h);

}  // namespace sph::job::distributed
