#include "job/RunStages.h"

#include <algorithm>
#include <csignal>
#include <cstring>

#include "io/MessageText.h"
#include "io/scene/SceneLoader.h"
#include "job/ExitCode.h"
#include "job/Interrupt.h"
#include "job/MachineMemory.h"
#include "job/Version.h"
#include "job/distributed/CollectiveCacheSink.h"
#include "job/distributed/DistributedResume.h"
#include "job/distributed/DistributedRun.h"
#include "job/distributed/StatusRecorder.h"
#include "render/cdt/CollisionSetup.h"
#include "sim/InputError.h"
#include "sim/Parallel.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::job {

using distributed::onRootAgreeing;

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
  c.ranks = distributed::world();
  c.root = distributed::isRootProcess();
  if (!c.root) c.request.quiet = true, c.request.verbose = false;
  c.scene = io::scene::loadScene(c.request.scene, c.request.overrides);
  if (c.request.end > 0) c.scene.solver.endTime = c.request.end;
  if (c.ranks) distributed::refuseUnsupported(c.scene, c.ranks->size());
}

StageResult checkMachine(RunContext& c) {
  cdt::requireIdsInRange(c.scene);
  setThreadCount(c.request.threads);  // first: DFSPH's estimate counts a spare pair chunk a thread
  // On K processes each rank's share, the ranks of a machine together (job/MachineMemory.h).
  c.memory = checkMemory(c.scene, c.ranks, c.ranks && !distributed::writeCacheTogether());
  if (!c.request.check) return std::nullopt;
  if (!c.request.quiet) c.observer.checked(c.request, c.scene, c.memory);
  return kOk;
}

StageResult openCache(RunContext& c) {
  if (!c.ranks) {
    c.cache = io::cache::CacheSession::prepare(c.request.cache, c.scene);
  } else {
    // Rank 0's checks stop every rank; prepare() may change the scene (a resume's frame rate),
    // and every rank must run the same scene.
    onRootAgreeing(*c.ranks,
                   [&] { c.cache = io::cache::CacheSession::prepare(c.request.cache, c.scene); });
    ranks::Bytes fps(sizeof(double));
    std::memcpy(fps.data(), &c.scene.output.fps, sizeof(double));
    c.ranks->broadcastFromRoot(fps);
    std::memcpy(&c.scene.output.fps, fps.data(), sizeof(double));
  }
  distributed::setLockstep(c.ranks != nullptr);
  // The pictures' directory is ours too before anything is written (the cache is, above).
  if (c.scene.render)
    c.framesLock =
        lockDirectory(RenderOutput::directoryFor(c.scene, c.cache ? c.cache->path() : ""));
  c.resumed = c.cache && c.cache->resuming();  // rank 0 knows; on K processes every rank learns
  if (!c.ranks) return std::nullopt;
  // Whether rank 0 resumes, before any fluid exists: a resume reads each rank's slab of the
  // cache's last frame, so no rank generates a start that would be dropped.
  const double end = c.scene.solver.endTime;
  std::vector<std::int64_t> resume{c.resumed ? 1 : 0, c.resumed && c.cache->lastFrameTime() >= end};
  c.ranks->sumInPlace(resume);
  c.resumed = resume[0] != 0;
  if (!resume[1]) return std::nullopt;
  if (c.root) c.observer.nothingToDo(c.cache->path(), c.cache->lastFrameTime());
  return kOk;
}

namespace {

// Every rank reads its slab of the cache's last frame (job/distributed/DistributedResume.h) once
// rank 0 has checked the cache against the scene; then rank 0 opens it for appending.
void resumeOnRanks(RunContext& c) {
  run::Simulation& sim = *c.sim;
  ranks::Communicator& ranks = *c.ranks;
  std::vector<std::int64_t> frame{0};
  onRootAgreeing(ranks, [&] {
    frame[0] = static_cast<std::int64_t>(c.cache->checkResume(sim, c.provenance));
  });
  ranks.sumInPlace(frame);
  c.nextFrame = static_cast<std::uint64_t>(frame[0]) + 1;
  ranks::Bytes path;
  if (c.root) path.assign(c.cache->path().begin(), c.cache->path().end());
  ranks.broadcastFromRoot(path);
  {
    std::unique_ptr<io::cache::CacheReader> own;
    if (!c.root)
      own = std::make_unique<io::cache::CacheReader>(std::string(path.begin(), path.end()));
    distributed::ResumePart part =
        distributed::readResumePart(*c.halo, c.root ? c.cache->reader() : *own,
                                    static_cast<std::size_t>(frame[0]), sim.params().h);
    io::cache::CacheSession::checkRecord(std::string(path.begin(), path.end()), part.state, sim);
    sim.restore(part.state, std::move(part.fluid), std::move(part.keys));
  }
  // Every rank's count (its reader is closed once it is in): the most any rank read.
  std::vector<std::int64_t> read(static_cast<std::size_t>(ranks.size()), 0);
  read[static_cast<std::size_t>(ranks.rank())] = static_cast<std::int64_t>(sim.fluid().size());
  ranks.sumInPlace(read);
  onRootAgreeing(ranks, [&] { c.cache->finishRestore(sim); });
  if (c.request.quiet) return;
  RunResume r;
  r.distributed = true;
  r.cachePath = c.cache->path();
  r.frame = c.nextFrame - 1;
  r.time = sim.time();
  r.note = c.cache->resumeNote();
  r.ranks = ranks.size();
  for (std::int64_t n : read) r.totalRead += n;
  r.mostRead = *std::max_element(read.begin(), read.end());
  c.observer.resumed(r);
}

}  // namespace

StageResult startSimulation(RunContext& c) {
  // On K processes the slabs exist before the fluid: each rank generates only its slab of the
  // starting fluid (sim/run/StartSlab.h), and no rank holds the whole of it; a resume starts
  // without fluid.
  const scene::Scene& scene = c.scene;
  if (c.ranks)
    c.halo = std::make_unique<ranks::Halo>(*c.ranks, scene.domain, scene.solver.supportRadius());
  const auto setupStart = std::chrono::steady_clock::now();
  // Samples the boundaries, once for the whole run.
  c.sim = c.halo ? std::make_unique<run::Simulation>(
                       scene, *c.halo,
                       c.resumed ? run::Simulation::Start::Empty : run::Simulation::Start::Slab)
                 : std::make_unique<run::Simulation>(scene);
  run::Simulation& sim = *c.sim;
  const double setupSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();
  sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
  std::size_t startParticles =
      c.halo ? c.halo->globalCount(sim.fluid().size()) : sim.fluid().size();
  // A distributed resume holds no fluid yet: the header tells the frame it continues from.
  if (c.halo && c.resumed && c.root)
    startParticles = c.cache->reader().summary().frames.at(c.cache->resumeFrame()).particles;
  if (!c.request.quiet)
    c.observer.started(
        {c.request, scene, sim, startParticles, c.cache.get(), setupSeconds, c.memory});

  c.provenance = {SPHSPLAT_VERSION_STRING, threadCount(), c.request.overrides};
  if (c.ranks) {
    if (c.resumed) resumeOnRanks(c);
  } else if (c.cache && c.cache->resuming()) {
    if (c.cache->lastFrameTime() >= scene.solver.endTime) {
      c.observer.nothingToDo(c.cache->path(), c.cache->lastFrameTime());
      return kOk;
    }
    c.nextFrame = c.cache->restore(sim, c.provenance) + 1;
    if (!c.request.quiet)
      c.observer.resumed({c.cache->path(), c.nextFrame - 1, sim.time(), c.cache->resumeNote()});
  }
  if (c.halo) sim.setHalo(c.halo.get());
  installInterruptHandlers();
  return std::nullopt;
}

void writingFailed(RunContext& c, const std::exception& e) {
  if (!c.request.quiet) c.observer.progressDone(sample(c));
  if (!c.cache) return;
  const std::string reason = std::string("writing failed: ") + e.what();
  // Failed in a frame the ranks write together: the cache's file is released mid-frame and the
  // other ranks may still write; the recorder writes the status once they have ended.
  if (distributed::statusRecorderArmed()) distributed::startStatusRecorder(reason.c_str());
  std::string kept;
  try {
    kept = c.cache->stop(reason);
    distributed::cancelStatusRecorder();
  } catch (const std::exception&) {
    kept = "the cache " + c.cache->path() + " keeps " + c.cache->framesText();
  }
  throw InputError(std::string(e.what()) + "; " + kept);
}

namespace {

// On K processes: with parallel HDF5 every rank writes its part of each frame
// (job/distributed/CollectiveCacheSink.h), else rank 0 gathers the frames and writes them.
void setUpDistributedOutputs(RunContext& c) {
  run::Simulation& sim = *c.sim;
  // Rank 0 knows whether there is a cache.
  std::vector<std::int64_t> caching{c.cache ? 1 : 0};
  c.ranks->sumInPlace(caching);
  c.framesTogether = caching[0] && !c.pictures && distributed::writeCacheTogether();
  if (c.framesTogether) {
    auto sink = std::make_unique<distributed::CollectiveCacheSink>(*c.halo, c.cache.get(), c.scene);
    c.frameSeconds = [p = sink.get()] { return p->seconds(); };
    c.collective = sink.get();
    c.distributedSink = std::move(sink);
  } else if (caching[0]) {
    // (Without a cache no rank has a sink, the renderer being refused on K processes: nothing
    // is gathered.)
    auto sink = std::make_unique<distributed::GatheringSink>(*c.halo, sim, c.sinks);
    c.frameSeconds = [p = sink.get()] { return p->seconds(); };
    c.distributedSink = std::move(sink);
  }
  c.sinks.clear();
  if (c.distributedSink) c.sinks.push_back(c.distributedSink.get());
  if (caching[0] && !c.resumed) {
    // Frame 0 as every later frame (each rank holds its slab of it): rank 0 creates the file
    // under PATH.partial (its checks stop every rank), all ranks write the frame, and rank 0
    // publishes it as PATH once the frame is committed.
    onRootAgreeing(*c.ranks, [&] {
      if (c.cache)
        c.cache->create(sim, c.provenance,
                        run::plannedFrameCount(c.plan.endTime, c.plan.frameInterval));
    });
    c.distributedSink->frame(sim, 0);
  }
}

}  // namespace

void setUpOutputs(RunContext& c) {
  run::Simulation& sim = *c.sim;
  c.start = std::chrono::steady_clock::now();
  c.plan.endTime = c.scene.solver.endTime;
  c.plan.frameInterval = 1.0 / c.scene.output.fps;
  c.plan.nextFrame = c.nextFrame;
  if (c.cache && !c.halo && !c.resumed) {
    try {
      c.cache->create(sim, c.provenance,
                      run::plannedFrameCount(c.plan.endTime, c.plan.frameInterval));
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
  if (c.cache) c.sinks.push_back(c.cache.get());
  if (c.pictures) c.sinks.push_back(c.pictures.get());
  if (c.halo) setUpDistributedOutputs(c);
}

StageResult runTheFrames(RunContext& c) {
  run::Simulation& sim = *c.sim;
  c.plan.stopRequested = [] { return interruptSignal() != 0; };
  // Every rank stops at the same step when any of them is told to.
  if (c.halo) c.plan.stopRequested = [&c] { return c.halo->any(interruptSignal() != 0); };
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
    distributed::setLockstep(false);  // every rank has the same error; rank 0 tells it
    if (!c.root) return kBlowUp;
    c.observer.blewUp(c.request, e, c.plan, outcome);
    if (c.cache) {
      char reason[96];
      std::snprintf(reason, sizeof reason, "numerical blow-up at step %llu, t = %.6g s",
                    static_cast<unsigned long long>(e.step), e.time);
      c.observer.cacheStopped(c.cache->stop(reason));
      distributed::cancelStatusRecorder();
    }
    return kBlowUp;
  }
  if (!c.request.quiet) c.observer.progressDone(sample(c));
  int signal = interruptSignal();
  // A distributed run stops when any rank was signalled (mpirun forwards SIGINT and SIGTERM).
  if (!signal && c.halo && outcome.end == run::RunOutcome::End::Stopped) signal = SIGTERM;
  if (!signal) return std::nullopt;
  distributed::setLockstep(false);
  if (!c.root) return 128 + signal;
  c.observer.interrupted(c.request, signal, sim.time());
  if (c.cache) {
    c.observer.cacheStopped(c.cache->stop(std::string("interrupted by ") + signalName(signal)));
    distributed::cancelStatusRecorder();  // started by the signal during a frame written together
    // A resume needs the same scene, edits, end and (for bit-exactness) threads.
    c.observer.canContinue(c.request, c.cache->path());
  }
  return 128 + signal;
}

void finish(RunContext& c) {
  run::Simulation& sim = *c.sim;
  if (c.cache) {
    try {
      c.cache->finish(sim.time());
    } catch (const std::exception& e) {
      writingFailed(c, e);
      throw;
    }
    distributed::cancelStatusRecorder();
  }
  RunSummary s(sim);
  s.endParticles = c.halo ? c.halo->globalCount(sim.fluid().size()) : sim.fluid().size();
  // A distributed run's throughput counts every rank's particles.
  s.particleSteps =
      c.halo ? c.halo->globalCount(sim.profile().particleSteps) : sim.profile().particleSteps;
  if (c.halo && c.request.verbose)
    s.exchanges = distributed::describeExchanges(*c.halo, sim.profile());
  s.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
  if (!c.request.quiet) {
    if (c.cache) s.cacheSummary = c.cache->summary(s.wallSeconds);
    s.ranks = c.ranks ? c.ranks->size() : 1;
    s.framesTogether = c.framesTogether;
    if (c.framesTogether) s.mpiIo = distributed::mpiIoChoice();
    if (c.frameSeconds) s.frameSeconds = c.frameSeconds();
    if (c.halo) s.haloStats = &c.halo->stats();
    if (c.collective && c.scene.rain && c.collective->frames() > 0)
      s.rainCellBytesPerFrame =
          static_cast<double>(c.collective->cellBytesReceived()) / c.collective->frames();
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
  distributed::setLockstep(false);
}

}  // namespace sph::job
