#include "job/distributed/mpi/FileErrorWatch.h"

#include <mpi.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

namespace sph::job::distributed::mpi {
namespace {

double gGrace = 0;
int gExitCode = 1;
std::atomic<bool> gStopping{false};  // this rank has told why it stops (noteStopping)
void (*gBeforeExit)(const char*) = nullptr;

extern "C" void onFileError(MPI_File*, int* code, ...) {
  static std::atomic<bool> watching{false};
  if (watching.exchange(true)) return;
  char text[MPI_MAX_ERROR_STRING] = {0};
  int length = 0;
  MPI_Error_string(*code, text, &length);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  // The error goes back to HDF5 as well (this handler returns), which normally fails the frame
  // and stops the run within the grace; the watch only ends a process stuck after it. It makes
  // no MPI call: the main thread may be inside one (MPI_THREAD_FUNNELED).
  const std::string what = "rank " + std::to_string(rank) + ": writing the cache failed (" + text +
                           ") and the ranks could not stop together";
  std::thread([what] {
    std::this_thread::sleep_for(std::chrono::duration<double>(gGrace));
    if (gBeforeExit) gBeforeExit(what.c_str());
    // One line per rank: a rank that has told its own failure only ends.
    if (!gStopping.load()) {
      std::fprintf(stderr, "sphsplat: %s; ending the run (the cache keeps its committed frames)\n",
                   what.c_str());
      std::fflush(stderr);
    }
    _exit(gExitCode);
  }).detach();
}

}  // namespace

void watchFileErrors(double graceSeconds, int exitCode, void (*beforeExit)(const char* line)) {
  gGrace = graceSeconds;
  gExitCode = exitCode;
  gBeforeExit = beforeExit;
  MPI_Errhandler handler;
  MPI_File_create_errhandler(onFileError, &handler);
  // The handler of MPI_FILE_NULL is the one files opened later start with.
  MPI_File_set_errhandler(MPI_FILE_NULL, handler);
}

void noteStopping() {
  gStopping.store(true);
}

}  // namespace sph::job::distributed::mpi
