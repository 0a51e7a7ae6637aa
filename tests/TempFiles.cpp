// Temporary files and directories of the test suites, removed when the test program ends well.
//
// Every suite writes scenes, caches and pictures under /tmp; a full run of the suite makes a few
// hundred of them, and they used to stay (16 GB after a day of runs on one machine). Each path
// made here is remembered, and when the program's tests have all passed a gtest listener removes
// it together with its siblings (the "-dir", ".d", ".h5" paths a test derives from a temporary
// name: they share its random stem). A failed program keeps them, and says where, so the failure
// can be looked at; SPHSPLAT_KEEP_TEST_FILES=1 keeps them always.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "tests/TestSupport.h"

namespace sph::test {
namespace {

namespace fs = std::filesystem;

struct Stem {
  fs::path directory;
  std::string prefix;  // the name up to the random part's end: siblings start with it
};

class TempFileCleaner : public ::testing::EmptyTestEventListener {
 public:
  void add(Stem stem) {
    std::lock_guard<std::mutex> lock(mutex_);
    stems_.push_back(std::move(stem));
  }

  void OnTestProgramEnd(const ::testing::UnitTest& unit) override {
    // A child forked by a test ends its copy of the program too: only the creator removes.
    if (getpid() != owner_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const char* keep = std::getenv("SPHSPLAT_KEEP_TEST_FILES");
    if (!unit.Passed() || (keep && *keep && std::string(keep) != "0")) {
      for (const Stem& s : stems_)
        std::fprintf(stderr, "[ kept ] %s*\n", (s.directory / s.prefix).c_str());
      return;
    }
    for (const Stem& s : stems_) removeWithSiblings(s);
    stems_.clear();
  }

 private:
  static void removeWithSiblings(const Stem& s) {
    std::error_code ec;
    std::vector<fs::path> doomed;
    for (fs::directory_iterator it(s.directory, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->path().filename().string().rfind(s.prefix, 0) == 0) doomed.push_back(it->path());
    }
    for (const fs::path& p : doomed) fs::remove_all(p, ec);
  }

  const pid_t owner_ = getpid();
  std::mutex mutex_;
  std::vector<Stem> stems_;
};

// Registered with gtest on first use, so the suites need no main() of their own; gtest owns it.
TempFileCleaner& cleaner() {
  static TempFileCleaner* instance = [] {
    auto* c = new TempFileCleaner;
    ::testing::UnitTest::GetInstance()->listeners().Append(c);
    return c;
  }();
  return *instance;
}

std::string tempRoot() {
  const char* dir = std::getenv("TMPDIR");
  return dir && *dir ? dir : "/tmp";
}

}  // namespace

std::string makeTempDirectory(const std::string& prefix) {
  std::string pattern = tempRoot() + "/" + prefix + "-XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (!mkdtemp(name.data())) throw std::runtime_error("mkdtemp failed: " + pattern);
  const fs::path path(name.data());
  cleaner().add({path.parent_path(), path.filename().string()});
  return path.string();
}

std::string writeTempFile(const std::string& text, const std::string& suffix) {
  std::string pattern = tempRoot() + "/sphsplat-test-XXXXXX" + suffix;
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = mkstemps(name.data(), static_cast<int>(suffix.size()));
  if (fd < 0) throw std::runtime_error("mkstemps failed: " + pattern);
  close(fd);
  std::ofstream(name.data()) << text;
  const fs::path path(name.data());
  const std::string file = path.filename().string();
  cleaner().add({path.parent_path(), file.substr(0, file.size() - suffix.size())});
  return path.string();
}

}  // namespace sph::test
