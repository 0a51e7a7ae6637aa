// Crash safety of the HDF5 cache: a run killed with SIGKILL at any moment leaves a file that opens,
// with the project's reader and with h5dump, and whose complete frames all read back bit for bit as
// an uninterrupted run wrote them; a killed run resumed to the end equals the uninterrupted run.
//
// Two ways of killing, both for real (no mocks): (1) a preload library (KillAtWrite.cpp) sends
// SIGKILL just before the N-th write to the cache, for every N of a run, which visits every state
// kill -9 can leave on disk (a process dies between system calls); (2) kill -9 from outside at
// moments spread over a run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/CacheSession.h"
#include "sim/InputError.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::fileExists;
using test::readFile;
using test::runShell;

std::vector<Particles> readAllFrames(const std::string& path) {
  io::cache::CacheReader reader(path);
  std::vector<Particles> frames;
  for (std::size_t k = 0; k < reader.frameCount(); ++k) frames.push_back(reader.readFrame(k));
  return frames;
}

// What a killed run left at `path`: a readable cache whose frames are a prefix of `reference`,
// h5dump reads all of it, and the sidecar is well-formed and lists no frame the file lacks.
// Returns the number of frames (0 when no cache was published yet).
std::size_t checkKilledCache(const std::string& path, const std::vector<Particles>& reference,
                             const std::string& label, bool* repaired = nullptr) {
  if (!fileExists(path)) return 0;  // killed before frame 0 was in: only PATH.partial exists
  std::size_t frames = 0;
  try {
    io::cache::CacheReader reader(path);
    frames = reader.frameCount();
    if (repaired) *repaired = reader.summary().repaired;
    EXPECT_GE(frames, 1u) << label << ": a published cache holds frame 0";
    EXPECT_TRUE(reader.summary().damagedFrame.empty())
        << label << ": " << reader.summary().damagedFrame;
    EXPECT_LE(frames, reference.size()) << label;
    for (std::size_t k = 0; k < frames && k < reference.size(); ++k) {
      EXPECT_TRUE(test::sameBits(reference[k], reader.readFrame(k))) << label << ", frame " << k;
      const auto [state, fluid] = reader.readRestart(k);
      EXPECT_EQ(fluid.size(), reference[k].size()) << label << ", resume record " << k;
    }
  } catch (const InputError& e) {
    ADD_FAILURE() << label << ": the project's reader refused the killed cache: " << e.what();
  }
  const auto dump = runShell("h5dump '" + path + "' > /dev/null");
  EXPECT_EQ(dump.exitCode, 0) << label << ": h5dump failed:\n" << dump.output;
  const std::string xdmfPath = path.substr(0, path.size() - 3) + ".xdmf";
  if (fileExists(xdmfPath)) {
    const std::string xdmf = readFile(xdmfPath);
    const std::string end = "</Xdmf>\n";
    EXPECT_TRUE(xdmf.size() > end.size() &&
                xdmf.compare(xdmf.size() - end.size(), end.size(), end) == 0)
        << label << ": the sidecar is cut short";
    std::size_t listed = 0;
    for (std::size_t pos = 0; (pos = xdmf.find("<Grid Name=\"Step#", pos)) != std::string::npos;
         ++pos)
      ++listed;
    EXPECT_LE(listed, frames) << label << ": the sidecar lists frames the cache does not hold";
  }
  return frames;
}

class CacheCrash : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::makeTempDir();
    scene_ = dir_ + "/tiny.json";
    std::ofstream(scene_) << test::tinyCacheScene(0.05, 100);
    const std::string countFile = dir_ + "/count", logFile = dir_ + "/writes.log";
    const auto ref = runShell(preload() + " SPHSPLAT_WRITE_COUNT_FILE='" + countFile +
                              "' SPHSPLAT_WRITE_LOG='" + logFile + "' " + run("ref.h5"));
    ASSERT_EQ(ref.exitCode, 0) << ref.output;
    writes_ = std::stol(readFile(countFile));
    reference_ = readAllFrames(dir_ + "/ref.h5");
    std::istringstream log(readFile(logFile));
    long n = 0;
    unsigned long long bytes = 0, offset = 0;
    while (log >> n >> bytes >> offset) {
      if (bytes > 0 && offset / 4096 != (offset + bytes - 1) / 4096) multiPageWrites_.push_back(n);
    }
    std::printf(
        "reference run: %ld writes to the cache and its sidecar, %zu of them across pages\n",
        writes_, multiPageWrites_.size());
  }

  static std::string preload() { return test::preloadInto(SPHSPLAT_KILL_SHIM); }
  // The command line of the run, writing `cache` in the test directory.
  static std::string run(const std::string& cache, const std::string& extra = "") {
    return "OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + scene_ +
           "' --threads 1 --quiet -o '" + dir_ + "/" + cache + "' " + extra;
  }

  static std::string dir_, scene_;
  static long writes_;
  static std::vector<Particles> reference_;
  static std::vector<long> multiPageWrites_;  // numbers of the writes that span a page boundary
};

std::string CacheCrash::dir_, CacheCrash::scene_;
long CacheCrash::writes_ = 0;
std::vector<Particles> CacheCrash::reference_;
std::vector<long> CacheCrash::multiPageWrites_;

TEST_F(CacheCrash, KilledBeforeEveryWriteOfARunLeavesItsFramesExact) {
  ASSERT_EQ(reference_.size(), 6u);  // 0.05 s at 100 frames/s
  ASSERT_GT(writes_, 30) << "the write counter saw too few writes to mean anything";
  std::map<std::size_t, int> framesSeen;
  for (long n = 1; n <= writes_; ++n) {
    const std::string cache = "kill" + std::to_string(n) + ".h5";
    const auto r =
        runShell(preload() + " SPHSPLAT_KILL_AT_WRITE=" + std::to_string(n) + " " + run(cache));
    ASSERT_EQ(r.exitCode, 128 + SIGKILL)
        << "write " << n << " of " << writes_ << ": the run was not killed\n"
        << r.output;
    const std::size_t frames = checkKilledCache(dir_ + "/" + cache, reference_,
                                                "killed before write " + std::to_string(n));
    framesSeen[frames]++;
    if (HasFailure()) break;
  }
  // Every stage of the run was hit: before the cache existed and with each frame count.
  for (std::size_t k = 0; k <= reference_.size(); ++k)
    EXPECT_GT(framesSeen[k], 0) << k << " frames never seen";
}

TEST_F(CacheCrash, AWriteTornAtAPageBoundaryLosesNoCommittedFrame) {
  // SIGKILL in the middle of a write that spans pages leaves its first page written: for each
  // such write of the run, the commits' root header rewrites among them, the reader restores the
  // root header from the journal where needed and every committed frame is still there.
  ASSERT_GE(multiPageWrites_.size(), reference_.size())
      << "expected a root header rewrite per frame at least";
  int repairs = 0;
  for (const char* keep : {"first", "last"}) {  // the page boundary where the write stops
    for (long n : multiPageWrites_) {
      const std::string cache = std::string("tear_") + keep + std::to_string(n) + ".h5";
      const auto r = runShell(preload() + " SPHSPLAT_TEAR_KEEP=" + keep +
                              " SPHSPLAT_TEAR_AT_WRITE=" + std::to_string(n) + " " + run(cache));
      ASSERT_EQ(r.exitCode, 128 + SIGKILL) << "write " << n << "\n" << r.output;
      bool repaired = false;
      const std::string label =
          std::string("write ") + std::to_string(n) + " torn at its " + keep + " page boundary";
      const std::size_t frames = checkKilledCache(dir_ + "/" + cache, reference_, label, &repaired);
      repairs += repaired;
      if (fileExists(dir_ + "/" + cache)) {
        EXPECT_GE(frames, 1u) << label;
      }
      if (HasFailure()) return;
    }
  }
  // Torn at its last boundary, each commit's root header misses its checksum: one repair a frame.
  EXPECT_GE(repairs, static_cast<int>(reference_.size()) - 1) << "the journal was not exercised";
}

TEST_F(CacheCrash, ResumingAKilledRunGivesTheUninterruptedRun) {
  // A few kill points across the run, each resumed to the end and compared frame by frame.
  int resumed = 0;
  for (long n = writes_ / 7; n < writes_; n += writes_ / 7) {
    const std::string cache = "resume" + std::to_string(n) + ".h5";
    runShell(preload() + " SPHSPLAT_KILL_AT_WRITE=" + std::to_string(n) + " " + run(cache));
    const std::string path = dir_ + "/" + cache;
    if (!fileExists(path)) continue;
    const auto r = runShell("OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" +
                            scene_ + "' --threads 1 --quiet --resume '" + path + "'");
    ASSERT_EQ(r.exitCode, 0) << "killed at write " << n << ", resume failed:\n" << r.output;
    const std::vector<Particles> frames = readAllFrames(path);
    ASSERT_EQ(frames.size(), reference_.size()) << "killed at write " << n;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      EXPECT_TRUE(test::sameBits(reference_[k], frames[k]))
          << "killed at write " << n << ", frame " << k;
    }
    ++resumed;
  }
  EXPECT_GE(resumed, 4);
}

TEST_F(CacheCrash, KilledBeforeEveryWriteOfAResumeThatRewritesAnOffGridFrame) {
  // A run that ended at 0.025 s, between the frames at 0.02 and 0.03 s, leaves frame 3 off the
  // frame grid; its resume removes that frame's records and writes frame 3 again at 0.03 s.
  // Killed before each of the resume's writes, the cache holds the old frames (frame 3 the
  // off-grid one) or a prefix of the uninterrupted run's, never part of either, and a second
  // resume ends it as the uninterrupted run.
  const std::string cut = dir_ + "/cut.h5";
  const auto first = runShell(run("cut.h5", "--end 0.025"));
  ASSERT_EQ(first.exitCode, 0) << first.output;
  std::vector<Particles> offGrid = readAllFrames(cut);
  ASSERT_EQ(offGrid.size(), 4u);
  ASSERT_EQ(io::cache::CacheReader(cut).summary().frames[3].time, 0.025);
  const std::string resume = "OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" +
                             scene_ + "' --threads 1 --quiet --resume ";
  const std::string copy = dir_ + "/resumed.h5";
  const std::string fresh = "cp '" + cut + "' '" + copy + "' && cp '" + dir_ + "/cut.xdmf' '" +
                            dir_ + "/resumed.xdmf' && ";
  const auto counted = runShell(fresh + preload() +
                                " SPHSPLAT_WRITE_COUNT_FILE='" + dir_ + "/resume.count' " +
                                resume + "'" + copy + "'");
  ASSERT_EQ(counted.exitCode, 0) << counted.output;
  const long writes = std::stol(readFile(dir_ + "/resume.count"));
  ASSERT_GT(writes, 10);
  std::map<std::string, int> seen;  // what the killed resumes left
  for (long n = 1; n <= writes; ++n) {
    const std::string label = "resume killed before write " + std::to_string(n);
    const auto r = runShell(fresh + preload() + " SPHSPLAT_KILL_AT_WRITE=" + std::to_string(n) +
                            " " + resume + "'" + copy + "'");
    ASSERT_EQ(r.exitCode, 128 + SIGKILL) << label << "\n" << r.output;
    const io::cache::CacheSummary s = io::cache::CacheReader(copy).summary();
    const bool old = s.frames.size() == 4 && s.frames[3].time == 0.025;
    checkKilledCache(copy, old ? offGrid : reference_, label);
    seen[old ? "the off-grid frame" : std::to_string(s.frames.size()) + " frames"]++;
    const auto again = runShell(resume + "'" + copy + "'");
    ASSERT_EQ(again.exitCode, 0) << label << ", then resumed:\n" << again.output;
    const std::vector<Particles> frames = readAllFrames(copy);
    ASSERT_EQ(frames.size(), reference_.size()) << label;
    for (std::size_t k = 0; k < frames.size(); ++k)
      EXPECT_TRUE(test::sameBits(reference_[k], frames[k])) << label << ", frame " << k;
    if (HasFailure()) break;
  }
  // Killed before the removal, after it (frame 3 gone), and with each later frame count.
  EXPECT_GT(seen["the off-grid frame"], 0);
  for (std::size_t k = 3; k <= reference_.size(); ++k)
    EXPECT_GT(seen[std::to_string(k) + " frames"], 0) << k << " frames never seen";
}

TEST_F(CacheCrash, AWriteRefusedAtAnyMomentEndsTheRunWithOneLineAndKeepsWhatWasCommitted) {
  // A full disk refuses one write (the preload library's ENOSPC) at each moment of a run with
  // --overwrite over an existing file: the run ends with exit 2 and one line, never a crash (HDF5
  // 1.10 keeps a file whose close failed, and closed it again at exit); before frame 0 is in,
  // the old file is untouched and no PATH.partial is left; after, the cache holds a prefix of
  // the run's frames and says why it stopped, or that it finished when only the last close failed.
  std::map<std::string, int> seen;
  for (long n = 1; n <= writes_; ++n) {
    const std::string label = "write " + std::to_string(n) + " refused";
    const std::string path = dir_ + "/full.h5";
    std::ofstream(path) << "an older file";
    const auto r = runShell(preload() + " SPHSPLAT_FAIL_AT_WRITE=" + std::to_string(n) + " " +
                            run("full.h5", "--overwrite"));
    ASSERT_EQ(r.exitCode, 2) << label << "\n" << r.output;
    ASSERT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << label << "\n" << r.output;
    EXPECT_FALSE(fileExists(path + ".partial")) << label;
    if (readFile(path) == "an older file") {
      EXPECT_NE(r.output.find("is as it was before the run"), std::string::npos) << r.output;
      seen["the old file"]++;
      continue;
    }
    const std::size_t frames = checkKilledCache(path, reference_, label);
    const std::string status = io::cache::CacheReader(path).summary().status;
    const bool finished = status.rfind("finished", 0) == 0;
    EXPECT_TRUE(status.rfind("stopped: writing failed: ", 0) == 0 || finished) << label << status;
    EXPECT_NE(r.output.find(" keeps frames 0-" + std::to_string(frames - 1)), std::string::npos)
        << label << "\n" << r.output;
    seen[finished ? "finished" : "stopped"]++;
    if (HasFailure()) break;
  }
  EXPECT_GT(seen["the old file"], 0);
  EXPECT_GT(seen["stopped"], 0);
  EXPECT_GT(seen["finished"], 0);
}

TEST_F(CacheCrash, RecordingAStopOfAKilledRunWritesOnlyOverItsOwnRunningStatus) {
  // The recorder of an MPI run that stopped in a frame its ranks wrote together
  // (job/distributed/StatusRecorder.h) records "stopped" over "running", and only over the state that run
  // left: not over a resume's status, nor over a cache with more frames than it could write.
  const std::string path = dir_ + "/record.h5";
  runShell(preload() + " SPHSPLAT_KILL_AT_WRITE=" + std::to_string(writes_ * 2 / 3) + " " +
           run("record.h5"));
  ASSERT_TRUE(fileExists(path));
  const auto status = [&] { return io::cache::CacheReader(path).summary().status; };
  ASSERT_EQ(status().rfind("running", 0), 0u) << status();
  const std::size_t frames = io::cache::CacheReader(path).frameCount();
  ASSERT_GE(frames, 2u);
  io::cache::CacheSession::recordStop(path, "the test's reason", frames - 1);
  EXPECT_EQ(status().rfind("running", 0), 0u) << "more frames than the run wrote: " << status();
  io::cache::CacheSession::recordStop(path, "the test's reason", frames);
  const std::string recorded =
      "stopped: the test's reason; last good frame " + std::to_string(frames - 1) + " (t = ";
  EXPECT_EQ(status().rfind(recorded, 0), 0u) << status();
  io::cache::CacheSession::recordStop(path, "another reason", frames);
  EXPECT_EQ(status().find("another reason"), std::string::npos) << status();
  const std::vector<Particles> kept = readAllFrames(path);
  ASSERT_EQ(kept.size(), frames);
  for (std::size_t k = 0; k < frames; ++k) EXPECT_TRUE(test::sameBits(reference_[k], kept[k]));
}

TEST_F(CacheCrash, KillNineFromOutsideAtMomentsSpreadOverARun) {
  // A longer run of the same scene (0.4 s, about 0.3 s of wall time in a release build, several
  // times that under the sanitizers or a busy machine), killed by another process at moments
  // spread over the reference run's own wall time, its start-up included.
  const std::string scene = dir_ + "/long.json";
  std::ofstream(scene) << test::tinyCacheScene(0.4, 100);
  const std::string refPath = dir_ + "/long_ref.h5";
  const auto started = std::chrono::steady_clock::now();
  const auto ref = runShell("OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + scene +
                            "' --threads 1 --quiet -o '" + refPath + "'");
  const double runMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  ASSERT_EQ(ref.exitCode, 0) << ref.output;
  const std::vector<Particles> reference = readAllFrames(refPath);
  int midRun = 0;
  for (double share : {0.02, 0.05, 0.1, 0.15, 0.2, 0.27, 0.33, 0.43, 0.53, 0.67, 0.83, 1.0}) {
    const int delayMs = static_cast<int>(share * runMs);
    const std::string path = dir_ + "/outside" + std::to_string(delayMs) + ".h5";
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
      execl(SPHSPLAT_BINARY, SPHSPLAT_BINARY, "run", scene.c_str(), "--threads", "1", "--quiet",
            "-o", path.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    const bool killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
    const std::size_t frames =
        checkKilledCache(path, reference, "kill -9 after " + std::to_string(delayMs) + " ms");
    if (killed && frames > 0 && frames < reference.size()) ++midRun;
  }
  EXPECT_GE(midRun, 3)
      << "too few kills landed while frames were being written (machine too slow or fast?)";
}

}  // namespace
}  // namespace sph
