// The subcommands of `sphsplat`. Each registers its options on the CLI11 app and returns the exit
// code of its run: 0 success, 1 internal error, 2 bad input (scene, cache, flags), 3 numerical
// blow-up stopped by the guard.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace sph::app {

enum ExitCode { kOk = 0, kInternalError = 1, kBadInput = 2, kBlowUp = 3 };

// Registers `run` and returns the function that executes it once parsed.
std::function<int()> addRunCommand(CLI::App& app);

}  // namespace sph::app
