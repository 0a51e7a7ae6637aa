// What both fuzzers share (fuzz/fuzz_cache.cpp, fuzz/fuzz_scene.cpp): their flags, and the tally
// of a run: outcomes counted, failed cases kept and said, the closing line and exit code.
#pragma once

#include <chrono>
#include <map>
#include <string>

#include "fuzz/ForkedCase.h"

namespace sph::fuzz {

struct FuzzOptions {
  long cases = 0;
  unsigned long long seed = 1;
  std::string keep = "fuzz-failures";  // where failed cases go
  double timeout = 20;                 // s, per command
  long renderEvery = 10;               // fuzz_cache: every K-th case also through `render`
  std::string replay;                  // a kept case, run once
  bool corpus = false;                 // fuzz_cache: the named damages instead of random ones
};

// --cases N --seed S --keep DIR --timeout SECONDS --replay FILE (and --render-every K and
// --corpus where `cacheFlags`); anything else prints `usage` and exits 2.
FuzzOptions parseFuzzOptions(int argc, char** argv, long defaultCases, bool cacheFlags,
                             const char* usage);

class FuzzTally {
 public:
  FuzzTally(std::string program, FuzzOptions options);
  // One command of case `k` ("info", `r` its result, `wrong` its verdict): counted, and when it
  // failed kept as DIR/`keptName` (its bytes `input`) and printed with `what` was changed and
  // the `command` that failed.
  void record(long k, const std::string& label, const CaseResult& r, const std::string& wrong,
              const std::string& what, const std::string& command, const std::string& keptName,
              const std::string& input);
  // A failure of case `k` that is no single command's.
  void fail(long k, const std::string& why);
  // Prints "PROGRAM: N cases in T s, F failed; outcome: count, ..." and returns the exit code.
  int finish() const;

 private:
  std::string program_;
  FuzzOptions options_;
  std::map<std::string, long> outcomes_;
  long failures_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace sph::fuzz
