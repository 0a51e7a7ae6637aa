// What `sphsplat run` does once its flags are parsed, as named stages (RunStages.h): load the
// scene, check the machine, open the cache, start the simulation (or resume it), set up the
// pictures, run the frames (sim/run/RunLoop.h), finish. What the user is told goes to a
// RunObserver: the terminal's words live in app/ (app/RunReport.h), a test can listen instead.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/cache/CacheSession.h"
#include "job/distributed/Processes.h"
#include "sim/StabilityError.h"
#include "sim/run/MemoryEstimate.h"
#include "sim/run/RunLoop.h"
#include "sim/run/Simulation.h"

namespace sph::job {

struct RunRequest {
  std::string scene;
  int threads = 0;  // 0: all cores
  double end = 0;   // s; 0: the scene's solver.end_time
  bool quiet = false;
  bool verbose = false;
  bool check = false;                  // --check: validate the scene and stop
  std::vector<std::string> overrides;  // --set KEY=VALUE
  io::cache::CacheSessionOptions cache;
};

// Where a run is, after a step.
struct RunSample {
  double time = 0, endTime = 0;  // s simulated
  std::uint64_t steps = 0;
  std::size_t particles = 0;
  double particleStepsPerSecond = 0;
};

// The simulation set up, before its first frame.
struct RunStart {
  const RunRequest& request;
  const scene::Scene& scene;
  const run::Simulation& sim;
  std::size_t fluidParticles;     // on all ranks
  const io::cache::CacheSession* cache;  // null without a cache (or on a rank other than 0)
  double setupSeconds;
  const run::MemoryEstimate& memory;
};

// A resume from a cache's frame.
struct RunResume {
  std::string cachePath;
  std::uint64_t frame = 0;   // the frame it continues from
  double time = 0;           // s
  std::string note;          // CacheSession::resumeNote()
  bool distributed = false;  // on K processes, each read its slab of the frame:
  int ranks = 1;
  long long mostRead = 0, totalRead = 0;
};

// How a run that reached its end went.
struct RunSummary {
  explicit RunSummary(const run::Simulation& s) : sim(s) {}
  const run::Simulation& sim;
  std::size_t endParticles = 0;     // on all ranks
  std::uint64_t particleSteps = 0;  // on all ranks
  double wallSeconds = 0;
  std::string cacheSummary;  // "" without a cache
  distributed::Report processes;
};

// What the user is told. Every call comes from the process that speaks (rank 0 of K).
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  // --check: the scene is valid and fits the machine.
  virtual void checked(const RunRequest&, const scene::Scene&, const run::MemoryEstimate&) {}
  // The cache to resume already reaches the end.
  virtual void nothingToDo(const std::string& /*cachePath*/, double /*time*/) {}
  virtual void started(const RunStart&) {}
  virtual void resumed(const RunResume&) {}
  // The scene's `settle`, before frame 0: after every settling step (its time runs to the
  // settle time) and once when the fluid has settled (`wallSeconds` it took); a blow-up while
  // settling (nothing is written).
  virtual void settling(const RunSample&) {}
  virtual void settled(const RunSample&, double /*wallSeconds*/) {}
  virtual void blewUpSettling(const StabilityError&) {}
  // After every step (cheap to receive), and once at the end of the stepping.
  virtual void progress(const RunSample&) {}
  virtual void progressDone(const RunSample&) {}
  // The run stopped early: a blow-up, or a signal at `time` (s). Then, with a cache, what it
  // keeps, and for an interrupt how to continue it.
  virtual void blewUp(const RunRequest&, const StabilityError&, const run::RunPlan&,
                      const run::RunOutcome&) {}
  virtual void interrupted(const RunRequest&, int /*signal*/, double /*time*/) {}
  virtual void cacheStopped(const std::string& /*kept*/) {}
  virtual void canContinue(const RunRequest&, const std::string& /*cachePath*/) {}
  virtual void finished(const RunRequest&, const RunSummary&) {}
};

// Returns the process's exit code (job/ExitCode.h).
int runJob(const RunRequest& request, RunObserver& observer);

}  // namespace sph::job
