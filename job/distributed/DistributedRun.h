// The parts of `sphsplat run` that differ when it runs on K processes (mpirun -np K; docs/
// scaling.md). MPI-free: the ranks are a ranks::Communicator, set by main() when an MPI starter
// launched the process (job/distributed/mpi/MpiCommunicator.h) and null otherwise.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sim/run/RunLoop.h"
#include "sim/scene/Scene.h"
#include "sim/run/Simulation.h"
#include "sim/ranks/Communicator.h"
#include "sim/ranks/Halo.h"

namespace sph::job::distributed {

// The ranks of this run (null: a plain single process).
ranks::Communicator* world();
void setWorld(ranks::Communicator* ranks);
// What the ranks write the cache with (job/distributed/mpi/MpiIoChoice.h: "ROMIO (romio321)"), for
// the summary.
const std::string& mpiIoChoice();
void setMpiIoChoice(std::string choice);
// True where messages are printed and files written: the only process, or rank 0.
bool isRootProcess();
// Set once the ranks run in lockstep (every rank in the same collectives): from then on an error
// on one rank alone must end them all (MpiSession::abortAll), or the others would wait forever.
void setLockstep(bool on);
bool inLockstep();

// What a run on `ranks` processes cannot do yet, refused with one line before anything runs:
// the collision pass and the renderer (single-process), a domain too thin for the slabs.
void refuseUnsupported(const scene::Scene& scene, int ranks);

// Runs `work` on rank 0 only; if it throws an InputError every rank throws it (so all stop with
// exit 2 and none is left waiting in a collective).
void onRootAgreeing(ranks::Communicator& ranks, const std::function<void()>& work);
// onRootAgreeing in two calls, for a caller that runs rank 0's work itself: rank 0's handler of
// the InputError `what` throws it on every rank; every rank calls followRoot() once rank 0 went
// on (it throws rank 0's error where rank 0 refused).
[[noreturn]] void refuseOnAllRanks(ranks::Communicator& ranks, const std::string& what);
void followRoot(ranks::Communicator& ranks);

// Rank 0's run state (time, step, emitters: a resume) on every rank.
run::RunState broadcastRunState(ranks::Communicator& ranks, const run::RunState& state);

// A frame sink for the ranks: gathers the fluid in the single process's order onto rank 0 and
// hands the frame to the real sinks (the cache) there, so they write the same file one process
// would.
class GatheringSink final : public run::FrameSink {
 public:
  GatheringSink(ranks::Halo& halo, run::Simulation& sim, std::vector<run::FrameSink*> sinks)
      : halo_(halo), sim_(sim), sinks_(std::move(sinks)) {}
  void frame(const run::Simulation& sim, std::size_t index) override;
  // Wall time in frame() on rank 0 (s): gathering and the sinks (run -v, docs/benchmarks.md).
  double seconds() const { return seconds_; }

 private:
  ranks::Halo& halo_;
  run::Simulation& sim_;
  std::vector<run::FrameSink*> sinks_;
  double seconds_ = 0;
};

// "2 ranks x 1 thread" style summary of a distributed run's exchanges (run --verbose).
std::string describeExchanges(ranks::Halo& halo, const solver::StepProfile& profile);

}  // namespace sph::job::distributed
