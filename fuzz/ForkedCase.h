// One fuzz case: `sphsplat` (its command line, in-process, app/CommandLine.h) run in a forked child,
// so that a crash, a hang or a huge allocation ends the child, not the harness. The child's
// standard output goes to /dev/null, its standard error is kept.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace sph::fuzz {

struct CaseResult {
  bool exited = false;  // else killed by `signal`
  int exitCode = 0;
  int signal = 0;
  bool timedOut = false;
  std::string errors;  // standard error
  // A single allocation larger than the case's limit (the child stopped at it); 0 if none.
  std::size_t oversizedAllocation = 0;
};

// Runs `sphsplat ARGS...` in a child for at most `timeoutSeconds`; the child stops at the first
// allocation of more than `allocationLimit` bytes.
CaseResult runForked(const std::vector<std::string>& args, double timeoutSeconds,
                     std::size_t allocationLimit);

// What a case must end with: exit 0, or exit 2 with one "sphsplat: " line (and nothing from
// HDF5's own error printing); `alsoAllowed` lists further exit codes that are an answer (3, a
// numerical blow-up, where damaged numbers are resumed). Empty if it did; else why not.
std::string verdict(const CaseResult& r, const std::vector<int>& alsoAllowed = {});

}  // namespace sph::fuzz
