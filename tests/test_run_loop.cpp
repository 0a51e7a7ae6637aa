// sim/run/RunLoop.h and io/cache/CacheSession.h driven in-process, the way `sphsplat run` drives
// them: frames at the planned times or at the stops a plan names, a stop between steps, a run
// that dies mid-way and is resumed from its cache, and a blow-up reported as an outcome.
// (tests/test_cache_crash.cpp kills real processes with SIGKILL; these check the library's own
// contract without a process boundary.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/CacheSession.h"
#include "io/scene/SceneLoader.h"
#include "sim/Parallel.h"
#include "sim/run/RunLoop.h"
#include "tests/CacheTestSupport.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

// Records every frame it is handed; can throw at one of them to play a crash.
class RecordingSink final : public run::FrameSink {
 public:
  std::vector<std::size_t> indices;
  std::vector<double> times;
  std::size_t crashAt = static_cast<std::size_t>(-1);
  void frame(const run::Simulation& sim, std::size_t index) override {
    if (index == crashAt) throw std::runtime_error("crash");
    indices.push_back(index);
    times.push_back(sim.time());
  }
};

scene::Scene tinyScene(double end, double fps = 100) {
  return io::scene::parseScene(test::tinyCacheScene(end, fps), "tiny.json");
}

run::RunPlan planFor(const scene::Scene& scene) {
  run::RunPlan plan;
  plan.endTime = scene.solver.endTime;
  plan.frameInterval = 1.0 / scene.output.fps;
  return plan;
}

TEST(RunLoop, HandsOverEveryFrameAtItsExactTime) {
  const scene::Scene scene = tinyScene(0.05);
  run::Simulation sim(scene);
  RecordingSink sink;
  const run::RunOutcome outcome = runFrames(sim, planFor(scene), {&sink});
  EXPECT_EQ(outcome.end, run::RunOutcome::End::Finished);
  EXPECT_FALSE(outcome.blowUp);
  ASSERT_EQ(sink.indices.size(), 5u);  // frames 1..5; frame 0 is the caller's
  for (std::size_t k = 0; k < sink.indices.size(); ++k) {
    EXPECT_EQ(sink.indices[k], k + 1);
    EXPECT_EQ(sink.times[k], std::min(0.05, (k + 1) * 0.01)) << "frame " << k + 1;
  }
  EXPECT_EQ(outcome.nextFrame, 6u);
  EXPECT_EQ(run::plannedFrameCount(0.05, 0.01), 6u);
}

// A sweep's stops (bench/sweep/SweepRunner.cpp): its own times, frames at k / fps and metric
// samples between them, each landed on exactly; every step between a before and an after call.
TEST(RunLoop, APlanLandsOnTheStopTimesItNames) {
  const scene::Scene scene = tinyScene(0.05);
  run::Simulation sim(scene);
  RecordingSink sink;
  run::RunPlan plan = planFor(scene);
  const std::vector<double> stops = {1.0 / 300, 0.01, 0.0137, 2.0 / 75, 0.04};
  plan.stopTime = [&](std::size_t k) { return k <= stops.size() ? stops[k - 1] : 1.0; };
  int before = 0, after = 0;
  plan.beforeStep = [&](const run::Simulation&) { EXPECT_EQ(before++, after); };
  plan.afterStep = [&](const run::Simulation&) { EXPECT_EQ(++after, before); };
  const run::RunOutcome outcome = runFrames(sim, plan, {&sink});
  EXPECT_EQ(outcome.end, run::RunOutcome::End::Finished);
  ASSERT_EQ(sink.times.size(), stops.size() + 1);  // and the end time, 0.05
  for (std::size_t k = 0; k < stops.size(); ++k) EXPECT_EQ(sink.times[k], stops[k]);
  EXPECT_EQ(sink.times.back(), 0.05);
  EXPECT_EQ(static_cast<std::uint64_t>(after), sim.stepCount());
}

TEST(RunLoop, AStopRequestEndsBetweenStepsWithoutAPartialFrame) {
  const scene::Scene scene = tinyScene(0.05);
  run::Simulation sim(scene);
  RecordingSink sink;
  run::RunPlan plan = planFor(scene);
  int steps = 0;
  plan.afterStep = [&](const run::Simulation&) { ++steps; };
  plan.stopRequested = [&] { return steps >= 7; };
  const run::RunOutcome outcome = runFrames(sim, plan, {&sink});
  EXPECT_EQ(outcome.end, run::RunOutcome::End::Stopped);
  EXPECT_EQ(steps, 7);
  EXPECT_EQ(sim.stepCount(), 7u);
  EXPECT_EQ(outcome.nextFrame, sink.indices.size() + 1);
  for (double t : sink.times) EXPECT_LE(t, sim.time());
  EXPECT_LT(sim.time(), 0.05);
}

TEST(RunLoop, ABlowUpIsAnOutcomeNamingStepAndParticle) {
  // The stress tables' must-stop case (tests/test_stress.cpp, GuardStops cfl 3.0).
  scene::Scene scene =
      test::shippedScene("dam_break", {"solver.spacing=0.0146", "solver.end_time=0.6",
                                       "solver.max_time_step=0.01", "solver.cfl=3.0"});
  run::Simulation sim(scene);
  RecordingSink sink;
  const run::RunOutcome outcome = runFrames(sim, planFor(scene), {&sink});
  ASSERT_EQ(outcome.end, run::RunOutcome::End::BlowUp);
  ASSERT_TRUE(outcome.blowUp);
  EXPECT_GT(outcome.blowUp->step, 0u);
  EXPECT_EQ(outcome.blowUp->step, sim.stepCount());
  EXPECT_NE(std::string(outcome.blowUp->what()).find("numerical blow-up at step"),
            std::string::npos);
}

// A run that dies at frame 6 of 11 (its cache session abandoned, as a crash leaves it) and is
// resumed from the cache ends bit for bit where the uninterrupted run does.
TEST(RunLoop, ACrashedRunResumedFromItsCacheEqualsTheUninterruptedRun) {
  const std::string dir = test::makeTempDir();
  const io::cache::CacheProvenance provenance{"test", threadCount(), {}};
  auto runToEnd = [&](const std::string& path, std::size_t crashAt) {
    scene::Scene scene = tinyScene(0.1);
    io::cache::CacheSessionOptions options;
    options.output = path;
    std::unique_ptr<io::cache::CacheSession> cache =
        io::cache::CacheSession::prepare(options, scene);
    run::Simulation sim(scene);
    cache->create(sim, provenance, run::plannedFrameCount(0.1, 0.01));
    cache->writeFrame(sim);
    RecordingSink crash;
    crash.crashAt = crashAt;
    EXPECT_THROW(runFrames(sim, planFor(scene), {cache.get(), &crash}), std::runtime_error);
  };
  const std::string whole = dir + "/whole.h5", crashed = dir + "/crashed.h5";
  {
    scene::Scene scene = tinyScene(0.1);
    io::cache::CacheSessionOptions options;
    options.output = whole;
    auto cache = io::cache::CacheSession::prepare(options, scene);
    run::Simulation sim(scene);
    cache->create(sim, provenance, run::plannedFrameCount(0.1, 0.01));
    cache->writeFrame(sim);
    EXPECT_EQ(runFrames(sim, planFor(scene), {cache.get()}).end, run::RunOutcome::End::Finished);
    cache->finish(sim.time());
    cache->close();
  }
  runToEnd(crashed, 6);  // frames 0-5 committed, then the crash
  EXPECT_EQ(io::cache::CacheReader(crashed).frameCount(), 7u)
      << "the cache sink writes frame 6 before the crashing sink sees it";
  {
    scene::Scene scene = tinyScene(0.1);
    io::cache::CacheSessionOptions options;
    options.resume = crashed;
    auto cache = io::cache::CacheSession::prepare(options, scene);
    ASSERT_TRUE(cache->resuming());
    run::Simulation sim(scene);
    run::RunPlan plan = planFor(scene);
    plan.nextFrame = cache->restore(sim, provenance) + 1;
    EXPECT_EQ(plan.nextFrame, 7u);
    EXPECT_EQ(runFrames(sim, plan, {cache.get()}).end, run::RunOutcome::End::Finished);
    cache->finish(sim.time());
    cache->close();
  }
  const io::cache::CacheReader a(whole), b(crashed);
  ASSERT_EQ(a.frameCount(), 11u);
  ASSERT_EQ(b.frameCount(), 11u);
  for (std::size_t k = 0; k < 11; ++k) {
    EXPECT_EQ(a.summary().frames[k].time, b.summary().frames[k].time);
    EXPECT_TRUE(test::sameBits(a.readFrame(k), b.readFrame(k))) << "frame " << k;
  }
}

}  // namespace
}  // namespace sph
