// Temporary files and directories of the test suites, removed when the test program ends well.
//
// Every suite writes scenes, caches and pictures under /tmp; a full run of the suite makes a few
// hundred of them, and they used to stay (16 GB after a day of runs on one machine). Each test
// program makes its files inside one directory of its own, $TMPDIR/sphsplat-test-XXXXXX (so the
// "-dir", ".d", ".h5" paths a test derives from a temporary name are in it too), and when the
// program's tests have all passed a gtest listener removes that directory. A failed program keeps
// it and says where, so the failure can be looked at; SPHSPLAT_KEEP_TEST_FILES=1 keeps it always.
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

// mkdtemp / mkstemps on a pattern held in a std::string.
std::string makeUnique(std::string pattern, int suffix, bool directory) {
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (directory) {
    if (!mkdtemp(name.data())) throw std::runtime_error("mkdtemp failed: " + pattern);
  } else {
    const int fd = mkstemps(name.data(), suffix);
    if (fd < 0) throw std::runtime_error("mkstemps failed: " + pattern);
    close(fd);
  }
  return name.data();
}

class TempFileCleaner : public ::testing::EmptyTestEventListener {
 public:
  // The program's own directory, made on first use.
  const std::string& root() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (root_.empty()) {
      const char* dir = std::getenv("TMPDIR");
      root_ =
          makeUnique(std::string(dir && *dir ? dir : "/tmp") + "/sphsplat-test-XXXXXX", 0, true);
    }
    return root_;
  }

  // Removes the directory now (a program about to replace itself with exec).
  void discard() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::error_code ec;
    if (!root_.empty()) fs::remove_all(root_, ec);
    root_.clear();
  }

  void OnTestProgramEnd(const ::testing::UnitTest& unit) override {
    // A child forked by a test ends its copy of the program too: only the creator removes.
    std::lock_guard<std::mutex> lock(mutex_);
    if (getpid() != owner_ || root_.empty()) return;
    const char* keep = std::getenv("SPHSPLAT_KEEP_TEST_FILES");
    if (!unit.Passed() || (keep && *keep && std::string(keep) != "0")) {
      std::fprintf(stderr, "[ kept ] %s\n", root_.c_str());
      return;
    }
    std::error_code ec;
    fs::remove_all(root_, ec);
    root_.clear();
  }

 private:
  const pid_t owner_ = getpid();
  std::mutex mutex_;
  std::string root_;
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

}  // namespace

std::string makeTempDirectory(const std::string& prefix) {
  return makeUnique(cleaner().root() + "/" + prefix + "-XXXXXX", 0, true);
}

void discardTempFiles() {
  cleaner().discard();
}

std::string writeTempFile(const std::string& text, const std::string& suffix) {
  const std::string path = makeUnique(cleaner().root() + "/sphsplat-test-XXXXXX" + suffix,
                                      static_cast<int>(suffix.size()), false);
  std::ofstream(path) << text;
  return path;
}

}  // namespace sph::test
