// `sphsplat run SCENE`: simulate a scene, report progress and a summary.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/Commands.h"
#include "app/Progress.h"
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

  Simulation sim(scene);
  const DerivedParams& d = sim.params();
  const double end = scene.solver.endTime;
  const double frameInterval = 1.0 / scene.output.fps;
  if (!o.quiet) {
    std::printf("%s: %zu fluid particles, %zu boundary particles, %d thread%s\n", scene.name.c_str(),
                sim.fluid().size(), sim.boundary().particles().size(), threadCount(),
                threadCount() == 1 ? "" : "s");
    std::printf("  spacing %g m, support radius %g m, particle mass %.4g kg, speed of sound %.3g m/s, "
                "first dt %.3g s\n",
                scene.solver.spacing, d.h, d.mass, d.speedOfSound, sim.nextTimeStep());
    if (o.verbose) {
      std::printf("  domain [%g, %g, %g] - [%g, %g, %g] m, %d boundary layer%s\n", scene.domain.lo.x(),
                  scene.domain.lo.y(), scene.domain.lo.z(), scene.domain.hi.x(), scene.domain.hi.y(),
                  scene.domain.hi.z(), d.boundaryLayers, d.boundaryLayers == 1 ? "" : "s");
      if (!scene.hasCollisionSection) std::printf("  skipped: collision pass (no collision section)\n");
      if (!scene.camera && !scene.hasRenderSection) std::printf("  skipped: render, GL context (no camera or render section)\n");
    }
    std::fflush(stdout);
  }

  Progress progress(Progress::detect(o.quiet), scene.name);
  const auto start = std::chrono::steady_clock::now();
  auto sample = [&]() {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ProgressSample s;
    s.time = sim.time();
    s.endTime = end;
    s.steps = sim.stepCount();
    s.particles = sim.fluid().size();
    s.particleStepsPerSecond = wall > 0 ? sim.profile().particleSteps / wall : 0;
    return s;
  };
  std::uint64_t frames = 1;  // the initial state is frame 0
  try {
    while (sim.time() < end) {
      const double nextFrame = std::min(end, static_cast<double>(frames) * frameInterval);
      while (sim.time() < nextFrame) {
        sim.step(nextFrame);
        progress.update(sample());
      }
      ++frames;
    }
  } catch (const StabilityError& e) {
    progress.finish(sample());
    std::fprintf(stderr, "sphsplat: %s\n", e.what());
    std::fprintf(stderr, "  reproduce: sphsplat run %s --end %.6g --threads %d\n", o.scene.c_str(), e.time,
                 threadCount());
    return kBlowUp;
  }
  progress.finish(sample());

  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const StepProfile& prof = sim.profile();
  if (!o.quiet) {
    std::printf("done: simulated %.4g s in %llu steps (mean dt %.3g s), %zu fluid particles at the end\n",
                sim.time(), static_cast<unsigned long long>(prof.steps),
                prof.steps ? sim.time() / prof.steps : 0.0, sim.fluid().size());
    std::printf("  wall time %s, %s particle-steps/s, %.3g ms per step\n", humanSeconds(wall).c_str(),
                humanCount(wall > 0 ? prof.particleSteps / wall : 0).c_str(),
                prof.steps ? 1e3 * wall / prof.steps : 0.0);
    if (o.verbose) printPassSplit(prof);
  }
  return kOk;
}

}  // namespace

std::function<int()> addRunCommand(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Simulate a scene file (JSON, see docs/scene-format.md)");
  cmd->add_option("scene", o->scene, "Scene file, e.g. scenes/dam_break.json")->required();
  cmd->add_option("--threads,-j", o->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--end", o->end, "Simulated end time in seconds (overrides solver.end_time)")->check(CLI::PositiveNumber);
  cmd->add_option("--set", o->overrides,
                  "Override a scene key before validation, KEY.PATH=VALUE, repeatable\n"
                  "(e.g. --set solver.spacing=0.01 --set fluids[0].velocity=[1,0,0])");
  cmd->add_flag("--quiet,-q", o->quiet, "No progress and no summary, only errors");
  cmd->add_flag("--verbose,-v", o->verbose, "Also print the domain, what the scene skips and the time per pass");
  cmd->footer("Exit codes: 0 done, 2 bad scene or flags, 3 numerical blow-up (the message names\n"
              "the step, time and particle), 1 internal error.");
  return [o, cmd]() { return cmd->parsed() ? run(*o) : -1; };
}

}  // namespace sph::app
