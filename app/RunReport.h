// The words of `sphsplat run`: the header before the run, the command that reproduces a blow-up
// or continues an interrupted run (runnable as printed), and the time per pass.
#pragma once

#include <string>

#include "job/RunJob.h"
#include "io/cache/CacheSession.h"
#include "sim/run/MemoryEstimate.h"
#include "sim/run/RunLoop.h"
#include "sim/run/Simulation.h"

namespace sph::app {

// `sphsplat run SCENE [--set ...] [--end T] --threads N` (under mpirun with its -np): the run as
// the user asked for it, with the end time `end` (0: the scene's own).
std::string commandLine(const job::RunRequest& o, double end);
// A POSIX shell word: as it is when it is safe, else in single quotes.
std::string shellQuote(const std::string& word);
// Runs to the blow-up and no further (see RunReport.cpp).
std::string reproduceCommand(const job::RunRequest& o, const run::RunPlan& plan,
                             const run::RunOutcome& outcome);
// What the run is about to do: particles (`fluidParticles`: on all ranks), the main derived
// numbers and, with --verbose, the domain and every piece of work the scene skips
// (docs/benchmarks.md, "What a scene skips").
void printHeader(const job::RunRequest& o, const scene::Scene& scene, const run::Simulation& sim,
                 std::size_t fluidParticles, const io::cache::CacheSession* cache,
                 double setupSeconds, const run::MemoryEstimate& memory);
// The share of the run's time in each pass (--verbose).
void printPassSplit(const solver::StepProfile& profile);

}  // namespace sph::app
