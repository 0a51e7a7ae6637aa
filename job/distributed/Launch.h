// How a process becomes one rank of a distributed run (docs/scaling.md), before its command line
// runs (app/main.cpp). An MPI starter (mpirun, mpiexec, srun) says in the environment that it
// launched the process (MpiStarter.h); MPI then starts, its ranks become world()
// (DistributedRun.h), and a watch ends a rank left stuck by a failed write of the cache
// (mpi/FileErrorWatch.h). A build without MPI refuses to be one of several processes. A plain
// `sphsplat` stays a plain process: nothing here starts MPI for it.
#pragma once

#include <memory>

namespace sph::job::distributed {

// A recorder that rank 0 of a distributed run started (StatusRecorder.h) is nothing else:
// returns its exit code, or -1 for any other process. First thing in main().
int runIfStatusRecorder(int argc, char** argv);

class Launch {
 public:
  // Reads the starter's variables; under one, starts MPI (which may edit argc and argv).
  // `badInput`: the exit code of a refused start and of a rank stuck after a failed write (2,
  // job/ExitCode.h, which is above this library).
  Launch(int* argc, char*** argv, int badInput);
  ~Launch();
  Launch(const Launch&) = delete;
  Launch& operator=(const Launch&) = delete;
  // The exit code the process must stop with before its command line, its line printed (a build
  // without MPI started as one of several processes: `badInput`); -1 to go on.
  int refusal() const { return refusal_; }

 private:
  struct Session;
  std::unique_ptr<Session> session_;  // MPI, until main() returns
  int refusal_ = -1;
};

// A rank that prints why it stops says so first (a watch that fires later adds no second line).
void noteStopping();
// Ends every rank at once with `code`: one rank failed alone while the others wait in a
// collective (inLockstep(), DistributedRun.h).
[[noreturn]] void abortAllRanks(int code);

}  // namespace sph::job::distributed
