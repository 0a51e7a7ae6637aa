// `sphsplat run SCENE`: simulate a scene, report progress and a summary.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/CacheOutput.h"
#include "app/CliChecks.h"
#include "app/CollisionSetup.h"
#include "app/Commands.h"
#include "app/Interrupt.h"
#include "app/Progress.h"
#include "app/RenderOutput.h"
#include "app/Version.h"
#include "io/SceneLoader.h"
#include "sim/Parallel.h"
#include "sim/Simulation.h"
#include "sim/StabilityError.h"

namespace sph::app {
namespace {

struct RunOptions {
  std::string scene;
  int threads = 0;
  double end = 0;
  bool quiet = false;
  bool verbose = false;
  std::vector<std::string> overrides;
  CacheFlags cache;
};

void printPassSplit(const StepProfile& profile) {
  const double total = profile.total();
  std::printf("  per pass:");
  for (int p = 0; p < static_cast<int>(Pass::Count); ++p) {
    const double s = profile.seconds[p];
    if (s <= 0) continue;
    std::printf(" %s %.1f%%", passName(static_cast<Pass>(p)), total > 0 ? 100 * s / total : 0.0);
  }
  std::printf("\n");
}

int run(const RunOptions& o) {
  Scene scene = io::loadScene(o.scene, o.overrides);
  if (o.end > 0) scene.solver.endTime = o.end;
  setThreadCount(o.threads);
  // The cache's paths are checked before anything runs (nothing is overwritten by surprise).
  std::unique_ptr<CacheOutput> cache = CacheOutput::prepare(o.cache, scene);

  const auto setupStart = std::chrono::steady_clock::now();
  Simulation sim(scene);  // samples the boundaries, once for the whole run
  const double setupSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();
  sim.setCollisionPass(makeCollisionPass(scene));
  const DerivedParams& d = sim.params();
  const double end = scene.solver.endTime;
  const double frameInterval = 1.0 / scene.output.fps;
  if (!o.quiet) {
    std::printf("%s: %zu fluid particles, %zu boundary particles, %d thread%s\n",
                scene.name.c_str(), sim.fluid().size(), sim.boundary().particles().size(),
                threadCount(), threadCount() == 1 ? "" : "s");
    std::printf(
        "  spacing %g m, support radius %g m, particle mass %.4g kg, speed of sound %.3g m/s, "
        "first dt %.3g s\n",
        scene.solver.spacing, d.h, d.mass, d.speedOfSound, sim.nextTimeStep());
    if (o.verbose) {
      std::printf("  domain [%g, %g, %g] - [%g, %g, %g] m, %d boundary layer%s\n",
                  scene.domain.lo.x(), scene.domain.lo.y(), scene.domain.lo.z(),
                  scene.domain.hi.x(), scene.domain.hi.y(), scene.domain.hi.z(), d.boundaryLayers,
                  d.boundaryLayers == 1 ? "" : "s");
      if (!scene.collision)
        std::printf("  skipped: collision pass (no collision section)\n");
      else
        std::printf("  collision: %s\n", describeCollision(scene).c_str());
      if (!scene.render) std::printf("  skipped: render, GL context (no render section)\n");
      // The other skips (docs/benchmarks.md, "What a scene skips").
      std::printf(
          "  skipped: boundary re-sampling (%zu boundary particles sampled once; setup took %s)\n",
          sim.boundary().particles().size(), humanSeconds(setupSeconds).c_str());
      if (!cache) {
        std::printf("  skipped: cache (no output path; --output or output.path writes one)\n");
      } else {
        std::string unwritten;
        for (std::size_t f = 0; f < io::cache::kFieldCount; ++f) {
          const std::string name = io::cache::fieldName(static_cast<io::cache::Field>(f));
          bool listed = false;
          for (const std::string& w : scene.output.fields) listed = listed || w == name;
          if (!listed) unwritten += (unwritten.empty() ? "" : " ") + name;
        }
        if (!unwritten.empty()) {
          std::printf("  skipped: cache fields not in output.fields (%s)%s\n", unwritten.c_str(),
                      scene.output.restart
                          ? "; resume records still keep what a resume needs (output.restart)"
                          : "");
        }
        std::printf(
            "  skipped: state between output frames (a frame every %.4g s, output.fps %g)\n",
            frameInterval, scene.output.fps);
      }
    }
    std::fflush(stdout);
  }

  std::uint64_t frames = 1;  // the next output frame; the initial state is frame 0
  const io::CacheProvenance provenance{SPHSPLAT_VERSION_STRING, threadCount(), o.overrides};
  if (cache && cache->resuming()) {
    if (cache->lastFrameTime() >= end) {
      std::printf("%s already reaches t = %g s; nothing to do (--end sets a later end time)\n",
                  cache->path().c_str(), cache->lastFrameTime());
      return kOk;
    }
    frames = cache->restore(sim, provenance) + 1;
    if (!o.quiet)
      std::printf("  resuming %s from frame %llu at t = %g s\n", cache->path().c_str(),
                  static_cast<unsigned long long>(frames - 1), sim.time());
  }
  installInterruptHandlers();

  Progress progress(Progress::detect(o.quiet), scene.name);
  const auto start = std::chrono::steady_clock::now();
  if (cache && !cache->resuming()) {
    const auto expectedFrames = static_cast<std::size_t>(std::ceil(end / frameInterval)) + 1;
    cache->create(sim, provenance, expectedFrames);
    cache->writeFrame(sim);
  }
  // Pictures while simulating (scene `render` section): the GL context exists only then.
  std::unique_ptr<RenderOutput> pictures =
      RenderOutput::prepare(scene, sim.boundary().particles(), cache ? cache->path() : "");
  if (pictures && !(cache && cache->resuming())) pictures->frame(sim.fluid(), 0, cache.get());
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
  try {
    while (sim.time() < end && !interruptSignal()) {
      const double nextFrame = std::min(end, static_cast<double>(frames) * frameInterval);
      while (sim.time() < nextFrame && !interruptSignal()) {
        sim.step(nextFrame);
        progress.update(sample());
      }
      if (sim.time() < nextFrame) break;  // interrupted within a frame: it is not written
      if (cache) cache->writeFrame(sim);
      if (pictures) pictures->frame(sim.fluid(), frames, cache.get());
      ++frames;
    }
  } catch (const StabilityError& e) {
    progress.finish(sample());
    std::fprintf(stderr, "sphsplat: %s\n", e.what());
    // The --set edits are part of the scene that blew up.
    std::string edits;
    for (const std::string& s : o.overrides) edits += " --set '" + s + "'";
    std::fprintf(stderr, "  reproduce: sphsplat run %s%s --end %.6g --threads %d\n",
                 o.scene.c_str(), edits.c_str(), e.time, threadCount());
    if (cache) {
      char reason[96];
      std::snprintf(reason, sizeof reason, "numerical blow-up at step %llu, t = %.6g s",
                    static_cast<unsigned long long>(e.step), e.time);
      std::fprintf(stderr, "  %s\n", cache->stop(reason).c_str());
    }
    return kBlowUp;
  }
  progress.finish(sample());
  if (const int signal = interruptSignal()) {
    std::fprintf(stderr, "sphsplat: interrupted by %s at t = %g s\n", signalName(signal),
                 sim.time());
    if (cache) {
      std::fprintf(stderr, "  %s\n",
                   cache->stop(std::string("interrupted by ") + signalName(signal)).c_str());
      std::string edits;  // a resume needs the same scene, edits and (for bit-exactness) threads
      for (const std::string& s : o.overrides) edits += " --set '" + s + "'";
      std::fprintf(stderr, "  continue with: sphsplat run %s%s --threads %d --resume %s\n",
                   o.scene.c_str(), edits.c_str(), threadCount(), cache->path().c_str());
    }
    return 128 + signal;
  }
  if (cache) cache->finish(sim.time());

  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const StepProfile& prof = sim.profile();
  if (!o.quiet) {
    std::printf(
        "done: simulated %.4g s in %llu steps (mean dt %.3g s), %zu fluid particles at the end\n",
        sim.time(), static_cast<unsigned long long>(prof.steps),
        prof.steps ? sim.time() / prof.steps : 0.0, sim.fluid().size());
    std::printf("  wall time %s, %s particle-steps/s, %.3g ms per step\n",
                humanSeconds(wall).c_str(),
                humanCount(wall > 0 ? prof.particleSteps / wall : 0).c_str(),
                prof.steps ? 1e3 * wall / prof.steps : 0.0);
    if (o.verbose) printPassSplit(prof);
    if (cache) std::printf("  %s\n", cache->summary(wall).c_str());
  }
  if (cache) cache->close();
  return kOk;
}

}  // namespace

std::function<int()> addRunCommand(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd =
      app.add_subcommand("run", "Simulate a scene file (JSON, see docs/scene-format.md)");
  cmd->add_option("scene", o->scene, "Scene file, e.g. scenes/dam_break.json")->required();
  cmd->add_option("--threads,-j", o->threads,
                  "Worker threads (default: all cores; at most 4 x the cores, more is refused)")
      ->check(threadsCheck());
  cmd->add_option("--end", o->end,
                  "Simulated end time in seconds, up to 1e6 (overrides solver.end_time)")
      ->check(positiveUpTo(io::kMaxEndTime, "seconds"));
  cmd->add_option("--set", o->overrides,
                  "Override a scene key before validation, KEY.PATH=VALUE, repeatable\n"
                  "(e.g. --set solver.spacing=0.01 --set fluids[0].velocity=[1,0,0])");
  cmd->add_flag("--quiet,-q", o->quiet, "No progress and no summary, only errors");
  cmd->add_flag("--verbose,-v", o->verbose,
                "Also print the domain, what the scene skips and the time per pass");
  cmd->add_option("--output,-o", o->cache.output,
                  "Write the HDF5 cache (and its .xdmf sidecar) to PATH; overrides output.path");
  cmd->add_flag("--overwrite", o->cache.overwrite, "Replace an existing cache at that path");
  cmd->add_flag("--no-compress", o->cache.noCompress, "Store the cache's datasets uncompressed");
  cmd->add_option("--resume", o->cache.resume,
                  "Continue the run in CACHE from its last complete frame, appending to it\n"
                  "(same scene and --set edits; same --threads for a bit-exact continuation)");
  cmd->footer(
      "Exit codes: 0 done, 2 bad scene, cache or flags, 3 numerical blow-up (the message\n"
      "names the step, time and particle, and the cache's last good frame), 1 internal\n"
      "error, 130/143 stopped by SIGINT/SIGTERM (the cache keeps every finished frame).");
  return [o, cmd]() { return cmd->parsed() ? run(*o) : -1; };
}

}  // namespace sph::app
