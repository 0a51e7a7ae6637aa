#include "app/RunJob.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/CollectiveCacheSink.h"
#include "app/ExitCode.h"
#include "app/DistributedResume.h"
#include "app/DistributedRun.h"
#include "app/Interrupt.h"
#include "app/MachineMemory.h"
#include "app/OpenMpSpinLimit.h"
#include "app/Progress.h"
#include "app/RenderOutput.h"
#include "app/RunReport.h"
#include "app/StatusRecorder.h"
#include "app/Version.h"
#include "io/MessageText.h"
#include "io/scene/SceneLoader.h"
#include "render/cdt/CollisionSetup.h"
#include "sim/InputError.h"
#include "sim/Parallel.h"
#include "sim/run/RunLoop.h"
#include "sim/run/Simulation.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::app {

int runJob(const RunRequest& request) {
  // On K processes (mpirun -np K; docs/scaling.md) every rank runs this; rank 0 alone prints
  // and writes the cache.
  ranks::Communicator* ranks = world();
  const bool root = isRootProcess();
  RunRequest o = request;
  if (!root) o.quiet = true, o.verbose = false;
  scene::Scene scene = io::loadScene(o.scene, o.overrides);
  if (o.end > 0) scene.solver.endTime = o.end;
  if (ranks) refuseUnsupported(scene, ranks->size());
  // Before anything is allocated: the CDT's id range (once --end is applied) and the machine's
  // memory; a scene past either stops here with one line naming the key to change.
  cdt::requireIdsInRange(scene);
  setThreadCount(o.threads);  // first: DFSPH's estimate counts a spare pair chunk a thread
  // On K processes each rank's share, the ranks of a machine together (app/MachineMemory.h).
  const run::MemoryEstimate memory = checkMemory(scene, ranks, ranks && !writeCacheTogether());
  if (o.check) {
    if (!o.quiet) {
      std::printf("%s: a valid scene (%s); memory: %s\n", io::oneLine(o.scene).c_str(),
                  io::oneLine(scene.name).c_str(),
                  describeMemory(memory, machineMemory()).c_str());
    }
    return kOk;
  }
  // The cache's paths are checked before anything runs (nothing is overwritten by surprise).
  std::unique_ptr<io::CacheSession> cache;
  if (!ranks) {
    cache = io::CacheSession::prepare(o.cache, scene);
  } else {
    // Rank 0's checks stop every rank; prepare() may change the scene (a resume's frame rate),
    // and every rank must run the same scene.
    onRootAgreeing(*ranks, [&] { cache = io::CacheSession::prepare(o.cache, scene); });
    ranks::Bytes fps(sizeof(double));
    std::memcpy(fps.data(), &scene.output.fps, sizeof(double));
    ranks->broadcastFromRoot(fps);
    std::memcpy(&scene.output.fps, fps.data(), sizeof(double));
  }
  setLockstep(ranks != nullptr);
  // The pictures' directory is ours too before anything is written (the cache is, above).
  io::OutputLock framesLock;
  if (scene.render)
    framesLock = lockDirectory(RenderOutput::directoryFor(scene, cache ? cache->path() : ""));

  const double end = scene.solver.endTime;
  const double frameInterval = 1.0 / scene.output.fps;
  bool resumed = cache && cache->resuming();  // rank 0 knows; on K processes every rank learns
  if (ranks) {
    // Whether rank 0 resumes, before any fluid exists: a resume reads each rank's slab of the
    // cache's last frame, so no rank generates a start that would be dropped.
    std::vector<std::int64_t> resume{cache && cache->resuming() ? 1 : 0,
                                     cache && cache->resuming() && cache->lastFrameTime() >= end};
    ranks->sumInPlace(resume);
    resumed = resume[0] != 0;
    if (resume[1]) {
      if (root)
        std::printf("%s already reaches t = %g s; nothing to do (--end sets a later end time)\n",
                    io::oneLine(cache->path()).c_str(), cache->lastFrameTime());
      return kOk;
    }
  }
  // On K processes the slabs exist before the fluid: each rank generates only its slab of the
  // starting fluid (sim/run/StartSlab.h), and no rank holds the whole of it; a resume starts
  // without fluid.
  std::unique_ptr<ranks::Halo> halo;
  if (ranks)
    halo = std::make_unique<ranks::Halo>(*ranks, scene.domain, solver::deriveParams(scene).h);
  const auto setupStart = std::chrono::steady_clock::now();
  // Samples the boundaries, once for the whole run.
  const std::unique_ptr<run::Simulation> simulation =
      halo ? std::make_unique<run::Simulation>(
                 scene, *halo,
                 resumed ? run::Simulation::Start::Empty : run::Simulation::Start::Slab)
           : std::make_unique<run::Simulation>(scene);
  run::Simulation& sim = *simulation;
  const double setupSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();
  sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
  std::size_t startParticles = halo ? halo->globalCount(sim.fluid().size()) : sim.fluid().size();
  // A distributed resume holds no fluid yet: the header tells the frame it continues from.
  if (halo && resumed && root) startParticles = cache->reader().summary().frames.at(cache->resumeFrame()).particles;
  if (!o.quiet) printHeader(o, scene, sim, startParticles, cache.get(), setupSeconds, memory);

  std::uint64_t frames = 1;  // the next output frame; the initial state is frame 0
  const io::CacheProvenance provenance{SPHSPLAT_VERSION_STRING, threadCount(), o.overrides};
  if (ranks) {
    if (resumed) {
      // Rank 0 checks the cache against the scene (its message stops every rank), then every
      // rank reads its slab of the last frame (app/DistributedResume.h), and once all have
      // closed the file rank 0 opens it for appending.
      std::vector<std::int64_t> frame{0};
      onRootAgreeing(*ranks, [&] {
        frame[0] = static_cast<std::int64_t>(cache->checkResume(sim, provenance));
      });
      ranks->sumInPlace(frame);
      frames = static_cast<std::uint64_t>(frame[0]) + 1;
      ranks::Bytes path;
      if (root) path.assign(cache->path().begin(), cache->path().end());
      ranks->broadcastFromRoot(path);
      {
        std::unique_ptr<io::CacheReader> own;
        if (!root) own = std::make_unique<io::CacheReader>(std::string(path.begin(), path.end()));
        ResumePart part = readResumePart(*halo, root ? cache->reader() : *own,
                                         static_cast<std::size_t>(frame[0]), sim.params().h);
        io::CacheSession::checkRecord(std::string(path.begin(), path.end()), part.state, sim);
        sim.restore(part.state, std::move(part.fluid), std::move(part.keys));
      }
      // Every rank's count (its reader is closed once it is in): the most any rank read.
      std::vector<std::int64_t> read(static_cast<std::size_t>(ranks->size()), 0);
      read[static_cast<std::size_t>(ranks->rank())] = static_cast<std::int64_t>(sim.fluid().size());
      ranks->sumInPlace(read);
      onRootAgreeing(*ranks, [&] { cache->finishRestore(sim); });
      if (!o.quiet) {
        long long all = 0;
        for (std::int64_t n : read) all += n;
        std::printf(
            "  resuming %s from frame %llu at t = %g s (each of the %d ranks read its slab of it: "
            "at most %lld of its %lld particles)%s\n",
            io::oneLine(cache->path()).c_str(), static_cast<unsigned long long>(frames - 1), sim.time(),
            ranks->size(), static_cast<long long>(*std::max_element(read.begin(), read.end())),
            all, cache->resumeNote().c_str());
      }
    }
  } else if (cache && cache->resuming()) {
    if (cache->lastFrameTime() >= end) {
      std::printf("%s already reaches t = %g s; nothing to do (--end sets a later end time)\n",
                  io::oneLine(cache->path()).c_str(), cache->lastFrameTime());
      return kOk;
    }
    frames = cache->restore(sim, provenance) + 1;
    if (!o.quiet)
      std::printf("  resuming %s from frame %llu at t = %g s%s\n", io::oneLine(cache->path()).c_str(),
                  static_cast<unsigned long long>(frames - 1), sim.time(),
                  cache->resumeNote().c_str());
  }
  if (halo) sim.setHalo(halo.get());
  installInterruptHandlers();

  Progress progress(Progress::detect(o.quiet), scene.name);
  const auto start = std::chrono::steady_clock::now();
  auto sample = [&]() {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ProgressSample s;
    s.time = sim.time();
    s.endTime = end;
    s.steps = sim.stepCount();
    s.particles = sim.fluid().size();
    s.particleStepsPerSecond = wall > 0 ? sim.profile().particleSteps / wall : 0;
    return s;
  };
  // Writing failed (a full disk, a file size limit, a vanished directory): the cache keeps its
  // committed frames and says why it stopped, instead of "running"; a new cache without its
  // frame 0 leaves nothing.
  auto writingFailed = [&](const std::exception& e) {
    progress.finish(sample());
    if (!cache) return;
    const std::string reason = std::string("writing failed: ") + e.what();
    // Failed in a frame the ranks write together: the cache's file is released mid-frame and
    // the other ranks may still write; the recorder writes the status once they have ended.
    if (statusRecorderArmed()) startStatusRecorder(reason.c_str());
    std::string kept;
    try {
      kept = cache->stop(reason);
      cancelStatusRecorder();
    } catch (const std::exception&) {
      kept = "the cache " + cache->path() + " keeps " + cache->framesText();
    }
    throw InputError(std::string(e.what()) + "; " + kept);
  };
  if (cache && !halo && !resumed) {
    try {
      cache->create(sim, provenance, run::plannedFrameCount(end, frameInterval));
      cache->writeFrame(sim);
    } catch (const std::exception& e) {
      writingFailed(e);
      throw;
    }
  }
  // Pictures while simulating (scene `render` section): the GL context exists only then.
  std::unique_ptr<RenderOutput> pictures =
      RenderOutput::prepare(scene, sim.boundary().particles(), cache.get());
  if (pictures && !resumed) {
    try {
      pictures->frame(sim, 0);
    } catch (const std::exception& e) {
      writingFailed(e);
      throw;
    }
  }
  run::RunPlan plan;
  plan.endTime = end;
  plan.frameInterval = frameInterval;
  plan.nextFrame = frames;
  plan.stopRequested = [] { return interruptSignal() != 0; };
  // Every rank stops at the same step when any of them is told to.
  if (halo) plan.stopRequested = [&halo] { return halo->any(interruptSignal() != 0); };
  plan.afterStep = [&](const run::Simulation&) { progress.update(sample()); };
  std::vector<run::FrameSink*> sinks;
  if (cache) sinks.push_back(cache.get());
  if (pictures) sinks.push_back(pictures.get());
  std::unique_ptr<run::FrameSink> distributed;
  std::function<double()> frameSeconds;  // rank 0's time handing frames out (run -v)
  bool together = false;
  const CollectiveCacheSink* collective = nullptr;  // run -v: the rain's water cells
  if (halo) {
    // Rank 0 knows whether there is a cache; with parallel HDF5 every rank writes its part of
    // each frame (app/CollectiveCacheSink.h), else rank 0 gathers the frames and writes them.
    std::vector<std::int64_t> caching{cache ? 1 : 0};
    ranks->sumInPlace(caching);
    together = caching[0] && !pictures && writeCacheTogether();
    if (together) {
      auto sink = std::make_unique<CollectiveCacheSink>(*halo, cache.get(), scene);
      frameSeconds = [p = sink.get()] { return p->seconds(); };
      collective = sink.get();
      distributed = std::move(sink);
    } else if (caching[0]) {
      // (Without a cache no rank has a sink, the renderer being refused on K processes: nothing
      // is gathered.)
      auto sink = std::make_unique<GatheringSink>(*halo, sim, sinks);
      frameSeconds = [p = sink.get()] { return p->seconds(); };
      distributed = std::move(sink);
    }
    sinks.clear();
    if (distributed) sinks.push_back(distributed.get());
    if (caching[0] && !resumed) {
      // Frame 0 as every later frame (each rank holds its slab of it): rank 0 creates the file
      // under PATH.partial (its checks stop every rank), all ranks write the frame, and rank 0
      // publishes it as PATH once the frame is committed.
      onRootAgreeing(*ranks, [&] {
        if (cache) cache->create(sim, provenance, run::plannedFrameCount(end, frameInterval));
      });
      distributed->frame(sim, 0);
    }
  }
  run::RunOutcome outcome;
  try {
    outcome = runFrames(sim, plan, sinks);
  } catch (const std::exception& e) {
    writingFailed(e);
    throw;
  }
  if (outcome.blowUp) {
    const StabilityError& e = *outcome.blowUp;
    progress.finish(sample());
    setLockstep(false);  // every rank has the same error; rank 0 tells it
    if (!root) return kBlowUp;
    std::fprintf(stderr, "sphsplat: %s\n", io::oneLine(e.what()).c_str());
    std::fprintf(stderr, "  reproduce: %s\n", reproduceCommand(o, plan, outcome).c_str());
    if (cache) {
      char reason[96];
      std::snprintf(reason, sizeof reason, "numerical blow-up at step %llu, t = %.6g s",
                    static_cast<unsigned long long>(e.step), e.time);
      std::fprintf(stderr, "  %s\n", io::oneLine(cache->stop(reason)).c_str());
      cancelStatusRecorder();
    }
    return kBlowUp;
  }
  progress.finish(sample());
  int signal = interruptSignal();
  // A distributed run stops when any rank was signalled (mpirun forwards SIGINT and SIGTERM).
  if (!signal && halo && outcome.end == run::RunOutcome::End::Stopped) signal = SIGTERM;
  if (signal) {
    setLockstep(false);
    if (!root) return 128 + signal;
    std::fprintf(stderr, "sphsplat: interrupted by %s at t = %g s\n", signalName(signal),
                 sim.time());
    if (cache) {
      std::fprintf(
          stderr, "  %s\n",
          io::oneLine(cache->stop(std::string("interrupted by ") + signalName(signal))).c_str());
      cancelStatusRecorder();  // started by the signal during a frame the ranks wrote together
      // A resume needs the same scene, edits, end and (for bit-exactness) threads.
      std::fprintf(stderr, "  continue with: %s --resume %s\n", commandLine(o, o.end).c_str(),
                   shellQuote(cache->path()).c_str());
    }
    return 128 + signal;
  }
  if (cache) {
    try {
      cache->finish(sim.time());
    } catch (const std::exception& e) {
      writingFailed(e);
      throw;
    }
    cancelStatusRecorder();
  }
  const std::size_t endParticles =
      halo ? halo->globalCount(sim.fluid().size()) : sim.fluid().size();
  // A distributed run's throughput counts every rank's particles.
  const std::uint64_t particleSteps =
      halo ? halo->globalCount(sim.profile().particleSteps) : sim.profile().particleSteps;
  if (halo && o.verbose) std::printf("  %s\n", describeExchanges(*halo, sim.profile()).c_str());

  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const solver::StepProfile& prof = sim.profile();
  if (!o.quiet) {
    std::printf(
        "done: simulated %.4g s in %llu steps (mean dt %.3g s), %zu fluid particles at the end\n",
        sim.time(), static_cast<unsigned long long>(prof.steps),
        prof.steps ? sim.time() / prof.steps : 0.0, endParticles);
    if (sim.lostParticles() > 0) {
      std::printf(
          "  %llu particles left the domain and were removed (solver.max_lost_particles = %llu)\n",
          static_cast<unsigned long long>(sim.lostParticles()),
          static_cast<unsigned long long>(sim.params().maxLostParticles));
    }
    if (const solver::PressureSolveStats& ds = sim.solveStats(); ds.steps > 0) {
      std::printf("  dfsph: %.2f density and %.2f divergence iterations per step\n",
                  static_cast<double>(ds.totalDensityIterations) / ds.steps,
                  static_cast<double>(ds.totalDivergenceIterations) / ds.steps);
    }
    std::printf("  wall time %s, %s particle-steps/s, %.3g ms per step\n",
                humanSeconds(wall).c_str(), humanCount(wall > 0 ? particleSteps / wall : 0).c_str(),
                prof.steps ? 1e3 * wall / prof.steps : 0.0);
    if (o.verbose) printPassSplit(prof);
    if (cache) std::printf("  %s\n", io::oneLine(cache->summary(wall)).c_str());
    if (together)
      std::printf("  frames written by all %d ranks together (parallel HDF5, MPI-IO: %s)\n",
                  ranks->size(), mpiIoChoice().c_str());
    if (o.verbose && frameSeconds) {
      std::printf("  frames: %.3g s on rank 0 to %s\n", frameSeconds(),
                  together ? "write them together" : "gather and write them");
      const ranks::HaloStats& hs = halo->stats();
      if (together && hs.placesCalls > 0)
        std::printf(
            "  their places (Halo::globalPlaces): %.3g ms, %llu bytes received and %llu "
            "keys sent to be placed a frame on rank 0\n",
            1e3 * hs.placesSeconds / hs.placesCalls,
            static_cast<unsigned long long>(hs.placesBytesReceived / hs.placesCalls),
            static_cast<unsigned long long>(hs.placesStrays / hs.placesCalls));
      if (collective && scene.rain && collective->frames() > 0)
        std::printf(
            "  rain: %.0f bytes of water cells received a frame on rank 0 from the other ranks "
            "(the drops meet their union; no particle is gathered)\n",
            static_cast<double>(collective->cellBytesReceived()) / collective->frames());
    }
  }
  if (cache) {
    try {
      cache->close();
    } catch (const std::exception& e) {
      // Every frame and the status are committed: the close's own writes failed (a full disk).
      throw InputError(std::string(e.what()) + "; the cache " + cache->path() + " keeps " +
                       cache->framesText() + ", its run finished");
    }
  }
  setLockstep(false);
  return kOk;
}

}  // namespace sph::app
