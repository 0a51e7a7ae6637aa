// The frame sink of an MPI run whose ranks write the cache together with parallel HDF5
// (docs/scaling.md, "The cache is written by all ranks"): each rank writes its own particles to
// their places in the single-process arrays, so the frames hold what one process would write
// and nothing is gathered. Rank 0 keeps everything else of the cache (creation, the first frame,
// statuses, the sidecar, the lock), as with the gathering sink (app/DistributedRun.h).
#pragma once

#include "io/CacheSession.h"
#include "sim/RunLoop.h"
#include "sim/dist/Halo.h"

namespace sph::app {

// Whether this run's cache is written by all ranks together: a build with parallel HDF5, and a
// scene without rain (its drops are stepped on the whole fluid, which rank 0 gathers instead).
bool writeCacheTogether(const Scene& scene);

class CollectiveCacheSink final : public FrameSink {
 public:
  // `cache`: rank 0's session; null on the other ranks.
  CollectiveCacheSink(dist::Halo& halo, io::CacheSession* cache) : halo_(halo), cache_(cache) {}
  void frame(const Simulation& sim, std::size_t index) override;
  // Wall time in frame() on this rank (s), finding the places included.
  double seconds() const { return seconds_; }

 private:
  double seconds_ = 0;
  dist::Halo& halo_;
  io::CacheSession* cache_;
};

}  // namespace sph::app
