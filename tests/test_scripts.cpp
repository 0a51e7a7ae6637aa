// The Python tools under scripts/ as a user starts them, `scripts/NAME.py ...`: each names Debian's
// interpreter, where scripts/setup installs h5py, numpy and matplotlib, rather than whichever
// python3 comes first on PATH (on a machine with pyenv or a virtual environment that one lacks
// them, and the script would stop at its first import).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "tests/TestSupport.h"

namespace sph {
namespace {

TEST(Scripts, EveryPythonToolStartsWithDebiansInterpreterWhateverIsFirstOnPath) {
  const std::string bin = test::makeTempDirectory("python-first-on-path");
  const std::string impostor = bin + "/python3";
  std::ofstream(impostor) << "#!/bin/sh\necho 'a python3 without Debian modules' >&2\nexit 97\n";
  ASSERT_EQ(::chmod(impostor.c_str(), 0755), 0);

  int scripts = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::sourcePath("scripts"))) {
    if (entry.path().extension() != ".py") continue;
    ++scripts;
    const std::string path = entry.path().string();
    EXPECT_EQ(::access(path.c_str(), X_OK), 0) << path << " is not executable";
    const auto r = test::runShell("PATH='" + bin + "':\"$PATH\" '" + path + "' --help");
    EXPECT_EQ(r.exitCode, 0) << path << ":\n" << r.output;
    EXPECT_NE(r.output.find("usage:"), std::string::npos) << path << ":\n" << r.output;
  }
  EXPECT_GE(scripts, 9);
}

}  // namespace
}  // namespace sph
