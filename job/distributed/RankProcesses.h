// A run on the K ranks an MPI starter launched (docs/scaling.md), as job/distributed/Processes.h
// asks: the slabs and their halo (sim/ranks/Halo.h) made before the fluid, rank 0's decisions
// agreed by all, a resume that reads each rank's slab of the cache's frame (DistributedResume.h),
// and the frames written by all ranks together (CollectiveCacheSink.h) or gathered onto rank 0
// (GatheringSink, DistributedRun.h).
#pragma once

#include <memory>

#include "job/distributed/Processes.h"

namespace sph::job::distributed {

std::unique_ptr<Processes> onRanks(ranks::Communicator& ranks);

}  // namespace sph::job::distributed
