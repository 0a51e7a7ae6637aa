// The run as a library (job/RunJob.h), in-process: the stages tell an observer what happened, a
// resume continues a cache bit for bit, a --check writes nothing. The same paths through the
// binary are tests/test_cache_resume.cpp and tests/test_cli.cpp; these see the stages' events
// themselves, which the terminal's words only paraphrase.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "job/ExitCode.h"
#include "job/RunJob.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

// Everything the stages said, in order, by name.
class Recorder final : public job::RunObserver {
 public:
  std::vector<std::string> events;
  std::vector<job::RunSample> samples;
  job::RunResume resume;
  std::string nothingToDoPath;
  double nothingToDoTime = -1;
  std::size_t startParticles = 0, endParticles = 0;

  void checked(const job::RunRequest&, const scene::Scene&, const run::MemoryEstimate&) override {
    events.push_back("checked");
  }
  void nothingToDo(const std::string& path, double time) override {
    events.push_back("nothingToDo"), nothingToDoPath = path, nothingToDoTime = time;
  }
  void started(const job::RunStart& s) override {
    events.push_back("started"), startParticles = s.fluidParticles;
  }
  void resumed(const job::RunResume& r) override { events.push_back("resumed"), resume = r; }
  void progress(const job::RunSample& s) override { samples.push_back(s); }
  void progressDone(const job::RunSample& s) override {
    events.push_back("progressDone"), samples.push_back(s);
  }
  void finished(const job::RunRequest&, const job::RunSummary& s) override {
    events.push_back("finished"), endParticles = s.endParticles;
  }
};

job::RunRequest request(const std::string& scene, const std::string& cache, double end) {
  job::RunRequest r;
  r.scene = scene;
  r.threads = 2;
  r.end = end;
  r.cache.output = cache;
  return r;
}

TEST(RunJob, TheStagesReportStartProgressAndEndInOrder) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.6, 30);
  Recorder seen;
  ASSERT_EQ(job::runJob(request(scene, dir + "/a.h5", 0.2), seen), job::kOk);
  EXPECT_EQ(seen.events, (std::vector<std::string>{"started", "progressDone", "finished"}));
  ASSERT_GT(seen.samples.size(), 2u);
  for (std::size_t i = 1; i < seen.samples.size(); ++i)
    EXPECT_GE(seen.samples[i].time, seen.samples[i - 1].time);
  EXPECT_EQ(seen.samples.back().time, 0.2);
  EXPECT_EQ(seen.samples.back().endTime, 0.2);
  // The nozzle adds particles: the summary counts the end's, the header the start's.
  const io::cache::CacheReader cache(dir + "/a.h5");
  EXPECT_EQ(seen.startParticles, cache.summary().frames.front().particles);
  EXPECT_EQ(seen.endParticles, cache.summary().frames.back().particles);
  EXPECT_GT(seen.endParticles, seen.startParticles);
}

TEST(RunJob, AResumeContinuesTheCacheAsTheStraightRunWroteIt) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.6, 30);
  Recorder straight, first, second;
  ASSERT_EQ(job::runJob(request(scene, dir + "/straight.h5", 0.6), straight), job::kOk);
  ASSERT_EQ(job::runJob(request(scene, dir + "/resumed.h5", 0.3), first), job::kOk);
  job::RunRequest resume = request(scene, "", 0.6);
  resume.cache.resume = dir + "/resumed.h5";
  ASSERT_EQ(job::runJob(resume, second), job::kOk);
  EXPECT_EQ(second.events,
            (std::vector<std::string>{"started", "resumed", "progressDone", "finished"}));
  EXPECT_FALSE(second.resume.distributed);
  EXPECT_EQ(second.resume.cachePath, dir + "/resumed.h5");
  EXPECT_EQ(second.resume.frame, 9u);  // 0.3 s at 30 frames/s
  EXPECT_EQ(second.resume.time, 0.3);
  test::expectSameCache(dir + "/straight.h5", dir + "/resumed.h5");
  EXPECT_EQ(second.endParticles, straight.endParticles);

  // A cache that already reaches the end: the header, then nothing to do, and the file as it was.
  Recorder third;
  ASSERT_EQ(job::runJob(resume, third), job::kOk);
  EXPECT_EQ(third.events, (std::vector<std::string>{"started", "nothingToDo"}));
  EXPECT_EQ(third.nothingToDoPath, dir + "/resumed.h5");
  EXPECT_EQ(third.nothingToDoTime, 0.6);
  test::expectSameCache(dir + "/straight.h5", dir + "/resumed.h5");
}

TEST(RunJob, ACheckStopsBeforeAnythingIsWritten) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.6, 30);
  job::RunRequest check = request(scene, dir + "/never.h5", 0);
  check.check = true;
  Recorder seen;
  EXPECT_EQ(job::runJob(check, seen), job::kOk);
  EXPECT_EQ(seen.events, (std::vector<std::string>{"checked"}));
  EXPECT_FALSE(test::fileExists(dir + "/never.h5"));
  EXPECT_FALSE(test::fileExists(dir + "/never.h5.partial"));
}

TEST(RunJob, AQuietRunTellsTheObserverNothing) {
  const std::string dir = test::makeTempDir();
  const std::string scene = dir + "/tiny.json";
  std::ofstream(scene) << test::tinyCacheScene(0.6, 30);
  job::RunRequest quiet = request(scene, dir + "/q.h5", 0.1);
  quiet.quiet = true;
  Recorder seen;
  EXPECT_EQ(job::runJob(quiet, seen), job::kOk);
  EXPECT_TRUE(seen.events.empty());
  EXPECT_TRUE(seen.samples.empty());
  EXPECT_EQ(io::cache::CacheReader(dir + "/q.h5").summary().frames.back().time, 0.1);
}

}  // namespace
}  // namespace sph
