// Helpers shared by the test suites: shipped scenes by name, the sphsplat binary, state hashes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/Particles.h"
#include "sim/scene/Scene.h"

namespace sph::test {

// Absolute path of a file in the source tree ("scenes/dam_break.json").
std::string sourcePath(const std::string& relative);
// Loads a shipped scene with overrides ("solver.spacing=0.01").
scene::Scene shippedScene(const std::string& name, const std::vector<std::string>& overrides = {});
// Martin & Moyce (1952)'s surge front, tests/data/martin_moyce_1952.csv: T = t sqrt(2g/a),
// Z = front / a.
struct SurgePoint {
  double T, Z;
};
std::vector<SurgePoint> martinMoyce();
// FNV-1a over the bytes of every particle field, in id order (independent of the sort).
std::uint64_t stateHash(const Particles& p);

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};
// The command line that starts the sphsplat binary under test (with the sanitizer options the
// binary needs in sanitizer builds); runSphsplat and the tests that spawn it themselves use it.
std::string sphsplatCommand();
// Runs a shell command line; its exit code and its stdout and stderr together.
CommandResult runShell(const std::string& command);
// Runs the sphsplat binary with the given argument string (shell-quoted by the caller).
CommandResult runSphsplat(const std::string& arguments);
// Runs `sh -c COMMAND` (stdout and stderr to a file) and returns its exit code, output and peak
// resident memory: the largest of the command and the processes it waited for (mpirun's ranks).
struct Measured {
  int exitCode = -1;
  double peakBytes = 0;
  std::string output;
};
Measured measure(const std::string& command);
// The bytes of `run --verbose`'s "memory: about 41.3 MB" line (0 if there is none).
double estimatedBytes(const std::string& output);

// Temporary files (tests/TempFiles.cpp): inside one directory of the test program's own under
// $TMPDIR or /tmp (with the paths a test derives from their names: NAME-dir, NAME.h5, ...),
// removed when every test of the program passed; kept and named when one failed or
// SPHSPLAT_KEEP_TEST_FILES=1.
// Writes `text` to a fresh temporary file with the given suffix and returns its path.
std::string writeTempFile(const std::string& text, const std::string& suffix = ".json");
// A fresh empty directory, PREFIX-XXXXXX.
std::string makeTempDirectory(const std::string& prefix = "sphsplat-test");
// Removes them now: for a program that replaces itself with exec before its tests run.
void discardTempFiles();

}  // namespace sph::test
