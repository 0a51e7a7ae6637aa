// The stages of a run (job/RunJob.h), in the order runJob() calls them, over one RunContext that
// each fills for the next. A stage that ends the run early (a --check, nothing left to do, a
// blow-up, an interrupt) returns the process's exit code; the others return nothing.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "io/OutputLock.h"
#include "io/cache/CacheSession.h"
#include "job/RenderOutput.h"
#include "job/RunJob.h"
#include "job/distributed/Processes.h"
#include "sim/run/MemoryEstimate.h"
#include "sim/run/RunLoop.h"
#include "sim/run/Simulation.h"

namespace sph::job {

struct RunContext {
  RunContext(const RunRequest& r, RunObserver& o) : request(r), observer(o) {}
  RunRequest request;  // quiet and not verbose on every rank but 0
  RunObserver& observer;
  // On K processes (mpirun -np K; docs/scaling.md) every rank runs the stages; rank 0 alone
  // speaks and writes the cache. Made first, it outlives what it was handed (the simulation,
  // the cache, the sinks).
  std::unique_ptr<distributed::Processes> processes;
  scene::Scene scene;
  run::MemoryEstimate memory;
  std::unique_ptr<io::cache::CacheSession> cache;
  io::OutputLock framesLock;
  bool resumed = false;  // every rank knows
  std::unique_ptr<run::Simulation> sim;
  std::uint64_t nextFrame = 1;  // the initial state is frame 0
  io::cache::CacheProvenance provenance;
  std::chrono::steady_clock::time_point start;  // of the stepping
  std::unique_ptr<RenderOutput> pictures;
  std::vector<run::FrameSink*> sinks;
  run::RunPlan plan;
};

using StageResult = std::optional<int>;  // an exit code ends the run

// The processes the run runs on; the scene with the request's --set and --end, refused on K
// processes if it asks for what a distributed run cannot do.
void loadScene(RunContext& c);
// The CDT's id range and the machine's memory: a scene past either stops here with one line
// naming the key to change. Ends a --check.
StageResult checkMachine(RunContext& c);
// The cache's paths (nothing is overwritten by surprise) and the pictures' directory; whether
// the run resumes. Ends a resume whose cache already reaches the end.
StageResult openCache(RunContext& c);
// The simulation, from the scene's start or the cache's last frame; the collision pass.
StageResult startSimulation(RunContext& c);
// The scene's `settle` for a run that starts from its scene (not a resume): the fluid settles
// and the clock starts again at 0. Ends a blow-up or an interrupt, before anything is written.
StageResult settleTheFluid(RunContext& c);
// Frame 0 in the cache and the first picture; where every later frame goes.
void setUpOutputs(RunContext& c);
// Steps to the end, a frame at each output time. Ends a blow-up or an interrupt.
StageResult runTheFrames(RunContext& c);
// The cache's status and the summary.
void finish(RunContext& c);

// A writing failure (a full disk, a file size limit, a vanished directory): the cache keeps its
// committed frames and says why it stopped; throws InputError saying so when there is a cache,
// else returns for the caller to rethrow.
void writingFailed(RunContext& c, const std::exception& e);
RunSample sample(const RunContext& c);

}  // namespace sph::job
