#include "bench/sweep/SweepRunner.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <memory>

#include "bench/sweep/SweepMetrics.h"
#include "io/scene/SceneLoader.h"
#include "render/cdt/CollisionSetup.h"
#include "sim/Parallel.h"
#include "sim/run/RunLoop.h"
#include "sim/run/Simulation.h"
#include "sim/solver/SceneSetup.h"

namespace sph::sweep {
namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Resident set size now (MB), from /proc/self/statm (Linux).
double residentMb() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0, resident = 0;
  if (!(statm >> pages >> resident)) return 0;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

std::string folderOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

scene::Scene variantScene(const SweepSpec& spec, const SweepVariant& v) {
  scene::Scene scene = io::scene::parseScene(v.sceneText, v.scenePath, v.edits);
  if (spec.endTime > 0) scene.solver.endTime = spec.endTime;
  return scene;
}

std::vector<std::unique_ptr<SweepMetric>> makeMetrics(const SweepSpec& spec) {
  std::vector<std::unique_ptr<SweepMetric>> metrics;
  for (std::size_t m = 0; m < spec.metrics.size(); ++m) {
    metrics.push_back(makeMetric(spec.metrics[m], spec.file, m, folderOf(spec.file)));
  }
  return metrics;
}

// The times (s) one metric observes at, sorted: its own samples and, if it asks, every frame.
std::vector<double> observationTimes(const SweepMetric& m, double end, double fps) {
  std::vector<double> t = m.sampleTimes();
  if (m.everyFrame()) {
    for (std::uint64_t k = 1; static_cast<double>(k) / fps <= end + 1e-12; ++k)
      t.push_back(static_cast<double>(k) / fps);
  }
  std::sort(t.begin(), t.end());
  t.erase(std::remove_if(t.begin(), t.end(), [&](double x) { return x > end + 1e-12; }), t.end());
  return t;
}

// Where the run must land, sorted: the output frames at k / fps, the end, and every metric's
// observation times, times within 1e-12 s of each other as one (the first). The sweeps' figures
// were measured on these stops; `sphsplat run`'s frames at k * (1 / fps) differ in the last bit
// for some k.
std::vector<double> landingTimes(const std::vector<std::vector<double>>& observations, double end,
                                 double fps) {
  std::vector<double> targets;
  for (std::uint64_t k = 1; static_cast<double>(k) / fps < end; ++k)
    targets.push_back(static_cast<double>(k) / fps);
  targets.push_back(end);
  for (const std::vector<double>& times : observations)
    targets.insert(targets.end(), times.begin(), times.end());
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end(),
                            [](double a, double b) { return std::abs(a - b) < 1e-12; }),
                targets.end());
  return targets;
}

// At each stop the run lands on, the metrics that asked for that time observe the state.
class MetricSampler final : public run::FrameSink {
 public:
  MetricSampler(std::vector<std::unique_ptr<SweepMetric>>& metrics,
                std::vector<std::vector<double>> times)
      : metrics_(metrics), times_(std::move(times)), cursor_(metrics.size(), 0) {}

  void frame(const run::Simulation& sim, std::size_t) override {
    for (std::size_t m = 0; m < metrics_.size(); ++m) {
      while (cursor_[m] < times_[m].size() && times_[m][cursor_[m]] <= sim.time() + 1e-12) {
        if (std::abs(times_[m][cursor_[m]] - sim.time()) < 1e-9) metrics_[m]->observe(sim);
        ++cursor_[m];
      }
    }
  }

 private:
  std::vector<std::unique_ptr<SweepMetric>>& metrics_;
  std::vector<std::vector<double>> times_;
  std::vector<std::size_t> cursor_;
};

// One run of one variant, through the run loop `sphsplat run` uses (sim/run/RunLoop.h). Metrics
// are restarted; the run lands exactly on every output frame and on every metric sample time.
VariantResult runOnce(const SweepSpec& spec, const SweepVariant& v, const scene::Scene& scene,
                      std::vector<std::unique_ptr<SweepMetric>>& metrics,
                      const MetricContext& context) {
  VariantResult r;
  r.variant = v;
  const Clock::time_point setupStart = Clock::now();
  run::Simulation sim(scene);
  sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
  if (scene.settle > 0) sim.settle(scene.settle);  // counted with the setup
  r.setupSeconds = seconds(setupStart, Clock::now());
  r.particles = sim.fluid().size();
  r.boundaryParticles = sim.boundary().particles().size();
  r.speedOfSound = sim.params().speedOfSound;
  r.stiffness = sim.params().stiffness;
  r.h = sim.params().h;
  r.speedBound = solver::expectedMaxSpeed(scene);

  const double end = scene.solver.endTime, fps = scene.output.fps;
  std::vector<std::vector<double>> times(metrics.size());
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    metrics[m]->start(sim, context);
    times[m] = observationTimes(*metrics[m], end, fps);
  }
  const std::vector<double> stops = landingTimes(times, end, fps);
  MetricSampler sampler(metrics, std::move(times));

  run::RunPlan plan;
  plan.endTime = stops.back();  // the end time, unless a sample within 1e-12 s before it stood in
  plan.stopTime = [&stops](std::size_t k) { return stops[std::min(k, stops.size()) - 1]; };
  // The steps alone are timed: not the metrics' sampling, nor the loop around them.
  Clock::time_point stepStart;
  double cpuStart = 0, wall = 0, cpu = 0;
  bool timedOut = false;
  // max_steps ends a run as finished (a stable row); max_wall_s as a timeout.
  plan.stopRequested = [&] {
    if (spec.maxSteps > 0 && sim.stepCount() >= spec.maxSteps) return true;
    timedOut = spec.maxWallSeconds > 0 && wall > spec.maxWallSeconds;
    return timedOut;
  };
  plan.beforeStep = [&](const run::Simulation&) {
    stepStart = Clock::now();
    cpuStart = processCpuSeconds();
  };
  plan.afterStep = [&](const run::Simulation& s) {
    cpu += processCpuSeconds() - cpuStart;
    wall += seconds(stepStart, Clock::now());
    r.maxSpeed = std::max(r.maxSpeed, static_cast<double>(s.runState().maxSpeed));
    for (auto& m : metrics) {
      if (m->stepInterval() > 0 && s.stepCount() % m->stepInterval() == 0) m->observe(s);
    }
  };
  const run::RunOutcome outcome = run::runFrames(sim, plan, {&sampler});
  if (outcome.blowUp) {
    r.status = RunStatus::Guard;
    r.guardStep = outcome.blowUp->step;
    r.guardTime = outcome.blowUp->time;
    r.message = outcome.blowUp->what();
  } else if (timedOut) {
    r.status = RunStatus::Timeout;
  } else {
    for (auto& m : metrics) m->finish(sim);
  }
  r.wallSeconds = wall;
  r.cpuSeconds = cpu;
  r.steps = sim.stepCount();
  r.simTime = sim.time();
  r.particlesEnd = sim.fluid().size();
  r.profile = sim.profile();
  r.rssMb = residentMb();
  for (auto& m : metrics) {
    for (double value : m->values())
      r.metrics.push_back(r.status == RunStatus::Stable ? value : std::nan(""));
  }
  return r;
}

}  // namespace

SweepResult runSweep(const SweepSpec& spec, const SweepRunOptions& options) {
  SweepResult result;
  result.spec = spec;
  std::vector<SweepVariant> variants = expandVariants(spec);
  if (!options.only.empty()) {
    variants.erase(std::remove_if(variants.begin(), variants.end(),
                                  [&](const SweepVariant& v) {
                                    return v.label.find(options.only) == std::string::npos;
                                  }),
                   variants.end());
  }
  // Nothing runs on a bad sweep: every scene and metric is checked first.
  std::vector<scene::Scene> scenes;
  for (const SweepVariant& v : variants) scenes.push_back(variantScene(spec, v));
  std::vector<std::unique_ptr<SweepMetric>> metrics = makeMetrics(spec);
  for (const auto& m : metrics) {
    for (const std::string& c : m->columns()) result.metricColumns.push_back(c);
  }

  setThreadCount(options.threads >= 0 ? options.threads : spec.threads);
  result.threads = threadCount();
  for (std::size_t i = 0; i < variants.size(); ++i) {
    MetricContext context;
    context.sweepFolder = folderOf(spec.file);
    context.seriesPrefix = options.outputDir + "/variant-" + std::to_string(i);
    VariantResult best;
    for (int repeat = 0; repeat < spec.repeats; ++repeat) {
      VariantResult r;
      try {
        r = runOnce(spec, variants[i], scenes[i], metrics, context);
      } catch (const InputError&) {
        throw;  // a metric that does not fit the scene: the sweep itself is wrong
      } catch (const std::exception& e) {
        r.variant = variants[i];
        r.status = RunStatus::Failed;
        r.message = e.what();
        r.metrics.assign(result.metricColumns.size(), std::nan(""));
      }
      const bool first = repeat == 0;
      if (first || (r.status == RunStatus::Stable && r.wallSeconds < best.wallSeconds))
        best = std::move(r);
      if (best.status != RunStatus::Stable) break;  // repeating a blow-up tells nothing new
    }
    if (options.onVariant) options.onVariant(best, result.metricColumns, i, variants.size());
    result.rows.push_back(std::move(best));
  }
  return result;
}

}  // namespace sph::sweep
