#include "job/RunStages.h"

#include <csignal>
#include <cstdio>

#include "io/MessageText.h"
#include "io/scene/SceneLoader.h"
#include "job/ExitCode.h"
#include "job/Interrupt.h"
#include "job/MachineMemory.h"
#include "job/Version.h"
#include "render/cdt/CollisionSetup.h"
#include "sim/InputError.h"
#include "sim/Parallel.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::job {
namespace {

// A step the root takes alone and may refuse (an InputError): the refusal stops every process
// with its line and exit 2 (Processes::refuseOnAll), none being left waiting in a collective.
template <class Step>
void onRoot(distributed::Processes& p, Step&& step) {
  if (p.root()) {
    try {
      step();
    } catch (const InputError& e) {
      p.refuseOnAll(e);
    }
  }
  p.followRoot();
}

}  // namespace

RunSample sample(const RunContext& c) {
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
  RunSample s;
  s.time = c.sim->time();
  s.endTime = c.scene.solver.endTime;
  s.steps = c.sim->stepCount();
  s.particles = c.sim->fluid().size();
  s.particleStepsPerSecond = wall > 0 ? c.sim->profile().particleSteps / wall : 0;
  return s;
}

void loadScene(RunContext& c) {
  c.processes = distributed::Processes::ofThisRun();
  if (!c.processes->root()) c.request.quiet = true, c.request.verbose = false;
  c.scene = io::scene::loadScene(c.request.scene, c.request.overrides);
  if (c.request.end > 0) c.scene.solver.endTime = c.request.end;
  c.processes->refuseUnsupported(c.scene);
}

StageResult checkMachine(RunContext& c) {
  cdt::requireIdsInRange(c.scene);
  setThreadCount(c.request.threads);  // first: DFSPH's estimate counts a spare pair chunk a thread
  // On K processes each rank's share, the ranks of a machine together (job/MachineMemory.h).
  c.memory = checkMemory(c.scene, c.processes->communicator(), c.processes->gathersFrames());
  if (!c.request.check) return std::nullopt;
  if (!c.request.quiet) c.observer.checked(c.request, c.scene, c.memory);
  return kOk;
}

StageResult openCache(RunContext& c) {
  distributed::Processes& p = *c.processes;
  // Rank 0's checks stop every rank; prepare() may change the scene (a resume's frame rate),
  // and every rank must run the same scene.
  onRoot(p, [&] { c.cache = io::cache::CacheSession::prepare(c.request.cache, c.scene); });
  p.fromRoot(c.scene.output.fps);
  p.setLockstep(true);
  // The pictures' directory is ours too before anything is written (the cache is, above).
  if (c.scene.render)
    c.framesLock =
        lockDirectory(RenderOutput::directoryFor(c.scene, c.cache ? c.cache->path() : ""));
  c.resumed = c.cache && c.cache->resuming();  // rank 0 knows; on K processes every rank learns
  const double end = c.scene.solver.endTime;
  if (!p.agreeOnResume(c.resumed, c.resumed && c.cache->lastFrameTime() >= end))
    return std::nullopt;
  if (p.root()) c.observer.nothingToDo(c.cache->path(), c.cache->lastFrameTime());
  return kOk;
}

StageResult startSimulation(RunContext& c) {
  distributed::Processes& p = *c.processes;
  const scene::Scene& scene = c.scene;
  const auto setupStart = std::chrono::steady_clock::now();
  // Samples the boundaries, once for the whole run.
  c.sim = p.makeSimulation(scene, c.resumed);
  run::Simulation& sim = *c.sim;
  const double setupSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();
  sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
  const std::size_t startParticles = p.startParticles(sim, c.cache.get(), c.resumed);
  if (!c.request.quiet)
    c.observer.started(
        {c.request, scene, sim, startParticles, c.cache.get(), setupSeconds, c.memory});

  c.provenance = {SPHSPLAT_VERSION_STRING, threadCount(), c.request.overrides};
  if (c.resumed) {
    // One process learns it here, after its header; K processes did before any fluid existed
    // (openCache), and only rank 0 holds the cache.
    if (c.cache && c.cache->lastFrameTime() >= scene.solver.endTime) {
      c.observer.nothingToDo(c.cache->path(), c.cache->lastFrameTime());
      return kOk;
    }
    // Rank 0 checks the cache against the scene (and notes another thread count), every process
    // reads the frame (K processes a slab each), and rank 0 opens the cache for appending.
    std::size_t last = 0;
    onRoot(p, [&] { last = c.cache->checkResume(sim, c.provenance); });
    const distributed::ResumeRead read = p.resume(sim, c.cache.get(), last);
    onRoot(p, [&] { c.cache->finishRestore(sim); });
    c.nextFrame = read.frame + 1;
    if (!c.request.quiet) {
      RunResume r;
      r.cachePath = c.cache->path();
      r.frame = read.frame;
      r.time = sim.time();
      r.note = c.cache->resumeNote();
      r.distributed = p.distributed();
      r.ranks = p.count();
      r.totalRead = read.totalRead;
      r.mostRead = read.mostRead;
      c.observer.resumed(r);
    }
  }
  p.startStepping(sim);
  installInterruptHandlers();
  return std::nullopt;
}

StageResult settleTheFluid(RunContext& c) {
  if (c.resumed || !(c.scene.settle > 0)) return std::nullopt;
  distributed::Processes& p = *c.processes;
  run::Simulation& sim = *c.sim;
  c.start = std::chrono::steady_clock::now();
  const auto settlingSample = [&c] {
    RunSample s = sample(c);
    s.endTime = c.scene.settle;
    return s;
  };
  RunSample last = settlingSample();  // the settling's, before the clock starts again
  const auto afterStep = [&](const run::Simulation&) {
    last = settlingSample();
    if (!c.request.quiet) c.observer.settling(last);
  };
  bool settled = false;
  try {
    settled = sim.settle(c.scene.settle, afterStep, [&p] { return p.any(interruptSignal() != 0); });
  } catch (const StabilityError& e) {
    p.setLockstep(false);  // every rank has the same error; rank 0 tells it
    if (p.root()) c.observer.blewUpSettling(e);
    return kBlowUp;
  }
  if (!settled) {
    const int signal = interruptSignal() ? interruptSignal() : SIGTERM;
    p.setLockstep(false);
    if (!p.root()) return 128 + signal;
    c.observer.interrupted(c.request, signal, sim.time());
    c.observer.cacheStopped("nothing was written: the fluid was settling (scene key settle)");
    return 128 + signal;
  }
  if (!c.request.quiet) {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
    c.observer.settled(last, wall);
  }
  return std::nullopt;
}

void writingFailed(RunContext& c, const std::exception& e) {
  if (!c.request.quiet) c.observer.progressDone(sample(c));
  if (!c.cache) return;
  const std::string reason = std::string("writing failed: ") + e.what();
  c.processes->writingFailed(reason);
  std::string kept;
  try {
    kept = c.cache->stop(reason);
    c.processes->statusRecorded();
  } catch (const std::exception&) {
    kept = "the cache " + c.cache->path() + " keeps " + c.cache->framesText();
  }
  throw InputError(std::string(e.what()) + "; " + kept);
}

void setUpOutputs(RunContext& c) {
  distributed::Processes& p = *c.processes;
  run::Simulation& sim = *c.sim;
  c.start = std::chrono::steady_clock::now();
  c.plan.endTime = c.scene.solver.endTime;
  c.plan.frameInterval = 1.0 / c.scene.output.fps;
  c.plan.nextFrame = c.nextFrame;
  const std::size_t plannedFrames = run::plannedFrameCount(c.plan.endTime, c.plan.frameInterval);
  // One process writes frame 0 before the pictures are set up (they show the drops its cache
  // steps); K processes write it together, through their sinks (below).
  if (c.cache && !c.resumed && !p.distributed()) {
    try {
      c.cache->create(sim, c.provenance, plannedFrames);
      c.cache->writeFrame(sim);
    } catch (const std::exception& e) {
      writingFailed(c, e);
      throw;
    }
  }
  // Pictures while simulating (scene `render` section): the GL context exists only then.
  c.pictures = RenderOutput::prepare(c.scene, sim.boundary().particles(), c.cache.get());
  if (c.pictures && !c.resumed) {
    try {
      c.pictures->frame(sim, 0);
    } catch (const std::exception& e) {
      writingFailed(c, e);
      throw;
    }
  }
  std::vector<run::FrameSink*> local;
  if (c.cache) local.push_back(c.cache.get());
  if (c.pictures) local.push_back(c.pictures.get());
  c.sinks = p.frameSinks(sim, c.cache.get(), c.scene, std::move(local), c.resumed, c.provenance,
                         plannedFrames);
}

StageResult runTheFrames(RunContext& c) {
  distributed::Processes& p = *c.processes;
  run::Simulation& sim = *c.sim;
  // Every rank stops at the same step when any of them is told to.
  c.plan.stopRequested = [&p] { return p.any(interruptSignal() != 0); };
  if (!c.request.quiet)
    c.plan.afterStep = [&](const run::Simulation&) { c.observer.progress(sample(c)); };
  run::RunOutcome outcome;
  try {
    outcome = runFrames(sim, c.plan, c.sinks);
  } catch (const std::exception& e) {
    writingFailed(c, e);
    throw;
  }
  if (outcome.blowUp) {
    const StabilityError& e = *outcome.blowUp;
    if (!c.request.quiet) c.observer.progressDone(sample(c));
    p.setLockstep(false);  // every rank has the same error; rank 0 tells it
    if (!p.root()) return kBlowUp;
    c.observer.blewUp(c.request, e, c.plan, outcome);
    if (c.cache) {
      char reason[96];
      std::snprintf(reason, sizeof reason, "numerical blow-up at step %llu, t = %.6g s",
                    static_cast<unsigned long long>(e.step), e.time);
      c.observer.cacheStopped(c.cache->stop(reason));
      p.statusRecorded();
    }
    return kBlowUp;
  }
  if (!c.request.quiet) c.observer.progressDone(sample(c));
  int signal = interruptSignal();
  // A distributed run stops when any rank was signalled (mpirun forwards SIGINT and SIGTERM);
  // one process stops only when it was.
  if (!signal && outcome.end == run::RunOutcome::End::Stopped) signal = SIGTERM;
  if (!signal) return std::nullopt;
  p.setLockstep(false);
  if (!p.root()) return 128 + signal;
  c.observer.interrupted(c.request, signal, sim.time());
  if (c.cache) {
    c.observer.cacheStopped(c.cache->stop(std::string("interrupted by ") + signalName(signal)));
    p.statusRecorded();  // started by the signal during a frame written together
    // A resume needs the same scene, edits, end and (for bit-exactness) threads.
    c.observer.canContinue(c.request, c.cache->path());
  }
  return 128 + signal;
}

void finish(RunContext& c) {
  distributed::Processes& p = *c.processes;
  run::Simulation& sim = *c.sim;
  if (c.cache) {
    try {
      c.cache->finish(sim.time());
    } catch (const std::exception& e) {
      writingFailed(c, e);
      throw;
    }
    p.statusRecorded();
  }
  RunSummary s(sim);
  s.endParticles = p.globalCount(sim.fluid().size());
  // A distributed run's throughput counts every rank's particles.
  s.particleSteps = p.globalCount(sim.profile().particleSteps);
  s.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
  if (!c.request.quiet) {
    if (c.cache) s.cacheSummary = c.cache->summary(s.wallSeconds);
    s.processes = p.report(sim, c.scene);
    c.observer.finished(c.request, s);
  }
  if (c.cache) {
    try {
      c.cache->close();
    } catch (const std::exception& e) {
      // Every frame and the status are committed: the close's own writes failed (a full disk).
      throw InputError(std::string(e.what()) + "; the cache " + c.cache->path() + " keeps " +
                       c.cache->framesText() + ", its run finished");
    }
  }
  p.setLockstep(false);
}

}  // namespace sph::job
