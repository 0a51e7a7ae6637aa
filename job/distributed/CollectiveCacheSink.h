// The frame sink of an MPI run whose ranks write the cache together with parallel HDF5
// (docs/scaling.md, "The cache is written by all ranks"): each rank writes its own particles to
// their places in the single-process arrays, so the frames hold what one process would write
// and nothing is gathered. Rank 0 keeps everything else of the cache (creation, the first frame,
// statuses, the sidecar, the lock), as with the gathering sink (job/distributed/DistributedRun.h).
#pragma once

#include <cstdint>
#include <memory>

#include "io/cache/CacheSession.h"
#include "sim/run/RunLoop.h"
#include "sim/ranks/Halo.h"
#include "sim/rain/RainSystem.h"

namespace sph::job::distributed {

// Whether this run's cache is written by all ranks together: a build with parallel HDF5.
bool writeCacheTogether();

class CollectiveCacheSink final : public run::FrameSink {
 public:
  // `cache`: rank 0's session; null on the other ranks. For a scene with rain (and a camera)
  // every rank sends rank 0 the water cells its particles occupy at each frame (not the
  // particles): rank 0 steps the drops with their union and writes them beside the frame.
  CollectiveCacheSink(ranks::Halo& halo, io::cache::CacheSession* cache, const scene::Scene& scene);
  void frame(const run::Simulation& sim, std::size_t index) override;
  // Wall time in frame() on this rank (s), finding the places included.
  double seconds() const { return seconds_; }
  // Rain: bytes of water-cell keys rank 0 received from the other ranks, and frames (run -v).
  std::uint64_t cellBytesReceived() const { return cellBytes_; }
  std::uint64_t frames() const { return frames_; }

 private:
  // This rank's occupied water cells; on rank 0 the union of every rank's, else null.
  std::unique_ptr<rain::WaterCells> gatherWater(const Particles& fluid);
  double seconds_ = 0;
  ranks::Halo& halo_;
  io::cache::CacheSession* cache_;
  float waterCell_ = 0;  // 0: no rain
  std::uint64_t cellBytes_ = 0, frames_ = 0;
};

}  // namespace sph::job::distributed
