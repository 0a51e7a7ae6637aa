// Checks of numeric flags shared by the subcommands. CLI11's own (NonNegativeNumber,
// PositiveNumber) let nan and inf through and print their limit as a 300-digit number; these
// refuse anything not finite and say the range as people write it ("--end: expected a number of
// seconds in (0, 1e6], got nan").
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace sph::app {

// --threads N: 0 (all cores) up to sim's maxThreadCount() (4 x the cores).
CLI::Validator threadsCheck();

// A finite number in (lo, hi] (lo excluded) with `unit` in the message ("seconds").
CLI::Validator positiveUpTo(double hi, const std::string& unit);

// An integer in [lo, hi].
CLI::Validator integerIn(long long lo, long long hi);

// CLI11's failure output made one line: "sphsplat: MESSAGE (see sphsplat [COMMAND] --help)".
std::string oneLineFailure(const CLI::App* app, const CLI::Error& e);

}  // namespace sph::app
