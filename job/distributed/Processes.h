// The processes a run runs on (docs/scaling.md): this one alone, or the K ranks an MPI starter
// launched (Launch.h). The run's stages (job/RunStages.h) make one in their first stage and ask it
// wherever a run on K processes differs, so they read the same on one process and on K. One
// process answers as a run without mpirun: its collectives are the identity, it refuses nothing,
// gathers nothing and writes its frames where the stages hand them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/cache/CacheSession.h"
#include "sim/InputError.h"
#include "sim/ranks/Communicator.h"
#include "sim/run/RunLoop.h"
#include "sim/run/Simulation.h"
#include "sim/scene/Scene.h"

namespace sph::ranks {
struct HaloStats;
}

namespace sph::job::distributed {

// What a resume read (Processes::resume).
struct ResumeRead {
  std::uint64_t frame = 0;  // the frame it continues from
  // K processes, each of which read its slab of the frame: the particles all read, the most one
  // read. 0 on one process.
  long long totalRead = 0, mostRead = 0;
};

// What the run's summary says of its processes.
struct Report {
  int ranks = 1;
  bool framesTogether = false;  // written by all ranks together (parallel HDF5)
  std::string mpiIo;            // with framesTogether: the MPI-IO component
  double frameSeconds = -1;     // K processes: rank 0's time handing frames out
  std::string exchanges;        // K processes: what the halo exchanged (printed by run -v)
  const ranks::HaloStats* haloStats = nullptr;  // K processes
  double rainCellBytesPerFrame = -1;            // frames written together with rain
};

class Processes {
 public:
  // K ranks when an MPI starter launched this process (world(), DistributedRun.h), else one.
  static std::unique_ptr<Processes> ofThisRun();
  virtual ~Processes() = default;

  // True where messages are printed and files written: the only process, or rank 0.
  virtual bool root() const = 0;
  // Started by an MPI starter, as K ranks (K may be 1).
  virtual bool distributed() const = 0;
  virtual int count() const = 0;
  // For the memory check (job/MachineMemory.h): the ranks (null alone), and whether rank 0
  // holds each frame whole to write it (gathered, without parallel HDF5).
  virtual ranks::Communicator* communicator() = 0;
  virtual bool gathersFrames() const = 0;

  // What K processes cannot do yet, refused with one line before anything runs.
  virtual void refuseUnsupported(const scene::Scene& scene) const = 0;
  // A step the root takes alone and may refuse (an InputError): the root's handler of the error
  // calls refuseOnAll, which throws it on every process, so all stop with exit 2 and none is left
  // waiting in a collective; every process calls followRoot() once the root went on. (Two
  // calls rather than a callback: the root's step stays in the stage that takes it, and what it
  // reads of the request goes no further down.)
  [[noreturn]] virtual void refuseOnAll(const InputError& error) = 0;
  virtual void followRoot() = 0;
  // The root's value on every process.
  virtual void fromRoot(double& value) = 0;
  // True on every process if `local` is on any (a signal seen by one rank stops all at the same
  // step), and a sum over them; on K processes once the simulation is made (its halo's).
  virtual bool any(bool local) = 0;
  virtual std::uint64_t globalCount(std::uint64_t local) = 0;
  // Set once every process runs the same collectives: from then on an error on one alone ends
  // them all (abortAllRanks, Launch.h), or the others would wait for ever.
  virtual void setLockstep(bool on) = 0;

  // Every process learns whether the root resumes (`resumed`) before any fluid exists: a
  // distributed resume reads each rank's slab of the cache's frame instead of generating one.
  // True when the run ends here, every process knowing that the root's cache already reaches the
  // end (`reachesEnd`); one process says so once its header is out (RunStages.cpp).
  virtual bool agreeOnResume(bool& resumed, bool reachesEnd) = 0;
  // The simulation (sampling the boundaries): from the scene's start, on K processes each rank's
  // slab of it (sim/run/StartSlab.h), or none when `resumed` (resume() reads it).
  virtual std::unique_ptr<run::Simulation> makeSimulation(const scene::Scene& scene,
                                                          bool resumed) = 0;
  // The fluid particles the header counts: on every process; a distributed resume holds none
  // yet, so the root's cache tells those of the frame it continues from.
  virtual std::size_t startParticles(const run::Simulation& sim,
                                     const io::cache::CacheSession* cache, bool resumed) = 0;
  // Restores `sim` from frame `frame` of the root's cache (both known on the root; null and 0
  // elsewhere) once the root has checked the cache against the scene (CacheSession::checkResume);
  // the root finishes the restore (CacheSession::finishRestore).
  virtual ResumeRead resume(run::Simulation& sim, io::cache::CacheSession* cache,
                            std::size_t frame) = 0;
  // Before the first step: on K processes the simulation becomes this rank's part.
  virtual void startStepping(run::Simulation& sim) = 0;

  // Where the frames go, `local` being the root's sinks (the cache, the pictures): one process
  // hands them the frames; K processes write the cache together (parallel HDF5) or gather the
  // frames onto rank 0 for them, and write frame 0 of a fresh start here (one process writes it
  // before its pictures are set up, RunStages.cpp).
  virtual std::vector<run::FrameSink*> frameSinks(run::Simulation& sim,
                                                  io::cache::CacheSession* cache,
                                                  const scene::Scene& scene,
                                                  std::vector<run::FrameSink*> local, bool resumed,
                                                  const io::cache::CacheProvenance& provenance,
                                                  std::size_t plannedFrames) = 0;

  // A write failed, maybe in a frame the ranks write together, in which the cache's file may be
  // released mid-frame while other ranks still write: rank 0's recorder (StatusRecorder.h) will
  // record `reason` once they have ended, unless statusRecorded() follows.
  virtual void writingFailed(const std::string& reason) = 0;
  // The cache's status is recorded by this process: a recorder started for it does nothing.
  virtual void statusRecorded() = 0;

  // What the summary says of the processes.
  virtual Report report(const run::Simulation& sim, const scene::Scene& scene) const = 0;
};

}  // namespace sph::job::distributed
