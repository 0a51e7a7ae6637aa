// `sphsplat`'s command line, in a function of its own so that a harness can run it in-process
// (fuzz/: a forked child per case).
#pragma once

namespace sph::app {

// Parses `argv` (argv[0] the program), runs the subcommand and returns the exit code
// (job/ExitCode.h); every failure is one line on standard error. The process set-up (standard
// streams, HDF5, OpenMP, MPI) is app/main.cpp's.
int runCommandLine(int argc, char** argv);

}  // namespace sph::app
