// Helpers of the HDF5 cache suites (tests/test_cache_*.cpp): a scene small enough that a cached
// run takes a fraction of a second, temporary directories, shell commands with an environment,
// and bit-for-bit comparison of particle arrays.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "sim/Particles.h"
#include "tests/TestSupport.h"

namespace sph::test {

// 96 particles in a box tank plus a nozzle adding a few more (so counts change between frames):
// about 0.3 ms a step. `extraOutput` is spliced into the output section (e.g. "\"restart\":
// false").
std::string tinyCacheScene(double endTime = 0.1, double fps = 100,
                           const std::string& extraOutput = "");

// The same scene with a camera and a `render` section: every frame drawn (quad splats, 96x64
// pixels, a few milliseconds each on llvmpipe) and stored in the cache.
std::string tinyRenderingScene(double endTime, double fps);

// A fresh empty directory under /tmp, removed after a passing run (makeTempDirectory).
std::string makeTempDir();

// A suite whose tests each write into a fresh directory of their own, dir_ (makeTempDir()).
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = makeTempDir(); }
  std::string dir_;
};

// The command that starts the sphsplat binary (sphsplatCommand, TestSupport.h).
std::string sphsplatBinary();

// The environment that loads the preload library `shim` (tests/KillAtWrite.cpp) into a child
// sphsplat: LD_PRELOAD='shim', and in a sanitizer build the AddressSanitizer runtime first, which
// it must be of the libraries a program loads.
std::string preloadInto(const std::string& shim);

// Every array present (non-empty or sized) in both, compared byte for byte.
::testing::AssertionResult sameBits(const Particles& expected, const Particles& actual);

// Every frame (time, step, arrays) and resume record (state, arrays) of cache `b` equals cache
// `a`'s, bit for bit (resume, and a run on K processes: tests/test_mpi.cpp).
void expectSameCache(const std::string& a, const std::string& b);
// `sphsplat ARGS` as a shell command with OMP_WAIT_POLICY=PASSIVE (no idle spinning while the
// suites run side by side), for runShell.
std::string sphsplatShell(const std::string& args);
// Lines in a command's output (a last line without a newline counts).
std::size_t lineCount(const std::string& s);

std::string readFile(const std::string& path);

// Every description on HDF5's error stack, innermost first (an open that fails names what went
// wrong a few levels up: "truncated file", "incorrect metadata checksum").
std::string hdf5ErrorStack();
// What h5py or ParaView do: open `path` read-only with the plain C API (no retry, no knowledge of
// the writer) and close it again. "" when that went well, else HDF5's messages.
std::string plainOpenError(const std::string& path);
bool fileExists(const std::string& path);

// A suite of CLI tests sharing one short run's cache (the tiny scene, 0.1 s, one thread),
// written once per suite into a temporary directory: dir_, scene_, cache_ and what the run
// printed, runOutput_.
class TinyCacheSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static std::string dir_, scene_, cache_;
  static CommandResult runOutput_;
};

}  // namespace sph::test
