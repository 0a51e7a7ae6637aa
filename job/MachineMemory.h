// The memory this process may use, and the check that refuses a run that would not fit: the
// estimate (sim/run/MemoryEstimate.h) against what the machine has free, a cgroup's memory.max
// and the process's address-space limit (ulimit -v), whichever is smallest. On K processes each
// rank checks its own share, and the ranks on one machine their sum against what that machine
// has free (docs/scaling.md, "Limits of this version": Memory).
#pragma once

#include <optional>
#include <string>

#include "sim/run/MemoryEstimate.h"
#include "sim/scene/Scene.h"
#include "sim/ranks/Communicator.h"

namespace sph::job {

struct MachineMemory {
  double totalBytes = 0;      // physical memory (MemTotal)
  double availableBytes = 0;  // free for this run: MemAvailable, or a tighter cgroup / ulimit
  std::string limitedBy;      // "" or what made it smaller than MemAvailable ("ulimit -v", ...)
  // Free for all the processes of this machine together: MemAvailable or a tighter cgroup (a
  // ulimit -v holds for each process alone).
  double sharedBytes = 0;
  std::string sharedLimitedBy;
};
MachineMemory machineMemory();

// Throws InputError naming the scene file, the estimate, the machine's memory and the scene key
// to change if the run (to solver.end_time) needs more than is available. Returns the estimate.
// With `ranks` (a run on K processes) it is collective: the estimate is one rank's share
// (RankShare; `gathersFrames` when rank 0 gathers the frames to write them), the ranks on each
// machine are counted together, and a refusal of any rank stops them all with its one line.
run::MemoryEstimate checkMemory(const scene::Scene& scene, ranks::Communicator* ranks = nullptr,
                                bool gathersFrames = false);

// Where this rank runs: how many of the run's ranks share its machine (the same host name),
// whether it is rank 0, and whether rank 0 runs on this machine (what only rank 0 holds counts
// there). One process: {1, true, true}.
struct RanksHere {
  int count = 1;
  bool rankZero = true;
  bool withRankZero = true;
};
// Collective.
RanksHere ranksOnThisMachine(ranks::Communicator& ranks);

// The refusal's text, if `estimate` (rank 0's, RankShare) does not fit `machine` for this rank
// and the ranks `here`: checkMemory without the collectives.
std::optional<std::string> memoryRefusal(const scene::Scene& scene,
                                         const run::MemoryEstimate& estimate,
                                         const MachineMemory& machine, const RanksHere& here);

// "about 41.3 MB (96 fluid particles, ...); the machine has 23.4 GB, 21.0 GB of it free" (or
// "..., of which ulimit -v leaves 921.6 MB").
std::string describeMemory(const run::MemoryEstimate& estimate, const MachineMemory& machine);

}  // namespace sph::job
