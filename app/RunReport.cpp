#include "app/RunReport.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "job/distributed/DistributedRun.h"
#include "job/MachineMemory.h"
#include "job/OpenMpSpinLimit.h"
#include "app/Progress.h"
#include "io/cache/CacheFormat.h"
#include "render/cdt/CollisionSetup.h"
#include "sim/Parallel.h"

namespace sph::app {

std::string shellQuote(const std::string& word) {
  bool plain = !word.empty();
  for (char ch : word) {
    const bool safe = std::isalnum(static_cast<unsigned char>(ch)) ||
                      std::string("/._-+=:,@%").find(ch) != std::string::npos;
    plain = plain && safe;
  }
  if (plain) return word;
  std::string quoted = "'";
  for (char ch : word) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return quoted + "'";
}

namespace {

// The shortest decimal text of t that reads back as at least t, so `--end TEXT` reaches it.
std::string endTimeText(double t) {
  char text[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, t);
    if (std::strtod(text, nullptr) >= t) break;
  }
  return text;
}

}  // namespace

void printPassSplit(const solver::StepProfile& profile) {
  const double total = profile.total();
  std::printf("  per pass:");
  for (int p = 0; p < static_cast<int>(solver::Pass::Count); ++p) {
    const double s = profile.seconds[p];
    if (s <= 0) continue;
    std::printf(" %s %.1f%%", passName(static_cast<solver::Pass>(p)),
                total > 0 ? 100 * s / total : 0.0);
  }
  std::printf("\n");
}

// `sphsplat run SCENE [--set ...] [--end T] --threads N`: the run as the user asked for it, with
// the end time `end` (0: the scene's own).
std::string commandLine(const job::RunRequest& o, double end) {
  std::string line = "sphsplat run " + shellQuote(o.scene);
  if (job::distributed::world()) line = "mpirun -np " + std::to_string(job::distributed::world()->size()) + " " + line;
  for (const std::string& s : o.overrides) line += " --set " + shellQuote(s);
  if (end > 0) line += " --end " + endTimeText(end);
  return line + " --threads " + std::to_string(threadCount());
}

// Runs to the blow-up and no further: to the end of the output frame it happened in. The steps
// before it are the same only if every step aims at the same frame time as the run did (the step
// is shortened to land on frames and on the end), so the end is that frame's time, not the time
// of the blow-up.
std::string reproduceCommand(const job::RunRequest& o, const run::RunPlan& plan,
                             const run::RunOutcome& outcome) {
  const double frameEnd = static_cast<double>(outcome.nextFrame) * plan.frameInterval;
  return commandLine(o, std::min(plan.endTime, frameEnd));
}

// What the run is about to do: particles, the main derived numbers and, with --verbose, the
// domain and every piece of work the scene skips (docs/benchmarks.md, "What a scene skips").
void printHeader(const job::RunRequest& o, const scene::Scene& scene, const run::Simulation& sim,
                 std::size_t fluidParticles, const io::cache::CacheSession* cache,
                 double setupSeconds, const run::MemoryEstimate& memory) {
  const solver::DerivedParams& d = sim.params();
  const double frameInterval = 1.0 / scene.output.fps;
  std::printf("%s: %zu fluid particles, %zu boundary particles, %s%d thread%s\n",
              scene.name.c_str(), fluidParticles, sim.boundary().particles().size(),
              job::distributed::world() ? (std::to_string(job::distributed::world()->size()) + " processes x ").c_str() : "",
              threadCount(), threadCount() == 1 ? "" : "s");
  std::printf(
      "  spacing %g m, support radius %g m, particle mass %.4g kg, speed of sound %.3g m/s, "
      "first dt %.3g s\n",
      scene.solver.spacing, d.h, d.mass, d.speedOfSound, sim.nextTimeStep());
  if (o.verbose) {
    std::printf("  memory: %s\n", job::describeMemory(memory, job::machineMemory()).c_str());
    std::printf("  OpenMP: %d thread%s, %s\n", threadCount(), threadCount() == 1 ? "" : "s",
                job::describeOpenMpWaiting());
    std::printf("  domain [%g, %g, %g] - [%g, %g, %g] m, %d boundary layer%s\n",
                scene.domain.lo.x(), scene.domain.lo.y(), scene.domain.lo.z(), scene.domain.hi.x(),
                scene.domain.hi.y(), scene.domain.hi.z(), d.boundaryLayers,
                d.boundaryLayers == 1 ? "" : "s");
    if (!scene.collision)
      std::printf("  skipped: collision pass (no collision section)\n");
    else
      std::printf("  collision: %s\n", render::cdt::describeCollision(scene).c_str());
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
      std::printf("  skipped: state between output frames (a frame every %.4g s, output.fps %g)\n",
                  frameInterval, scene.output.fps);
    }
  }
  std::fflush(stdout);
}

}  // namespace sph::app
