// The memory this process may use, and the check that refuses a run that would not fit (issue
// 12, item 6): the estimate (sim/MemoryEstimate.h) against what the machine has free, a cgroup's
// memory.max and the process's address-space limit (ulimit -v), whichever is smallest.
#pragma once

#include <string>

#include "sim/MemoryEstimate.h"
#include "sim/Scene.h"

namespace sph::app {

struct MachineMemory {
  double totalBytes = 0;      // physical memory (MemTotal)
  double availableBytes = 0;  // free for this run: MemAvailable, or a tighter cgroup / ulimit
  std::string limitedBy;      // "" or what made it smaller than MemAvailable ("ulimit -v", ...)
};
MachineMemory machineMemory();

// Throws InputError naming the scene file, the estimate, the machine's memory and the scene key
// to change if the run (to solver.end_time) needs more than is available. Returns the estimate.
MemoryEstimate checkMemory(const Scene& scene);

// "about 41.3 MB (96 fluid particles, ...); the machine has 21.0 GB free of 23.4 GB".
std::string describeMemory(const MemoryEstimate& estimate, const MachineMemory& machine);

}  // namespace sph::app
