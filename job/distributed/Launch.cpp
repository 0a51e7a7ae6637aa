#include "job/distributed/Launch.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "job/distributed/DistributedRun.h"
#include "job/distributed/MpiStarter.h"
#include "job/distributed/StatusRecorder.h"
#ifdef SPHSPLAT_MPI
#include "job/distributed/mpi/FileErrorWatch.h"
#include "job/distributed/mpi/MpiCommunicator.h"
#include "job/distributed/mpi/MpiIoChoice.h"
#endif

namespace sph::job::distributed {

int runIfStatusRecorder(int argc, char** argv) {
  if (argc != kRecorderArgc || std::strcmp(argv[1], kRecorderArgument) != 0) return -1;
  return runStatusRecorder(argv);
}

#ifdef SPHSPLAT_MPI

struct Launch::Session {
  mpi::MpiSession mpi;
  Session(int* argc, char*** argv) : mpi(argc, argv) {}
};

Launch::Launch(int* argc, char*** argv, int badInput) {
  if (!mpiStarter().launched) return;
  // Open MPI's OMPIO locks the whole file around each write on NFS (its automatic choice), which
  // would wait for ever on the run's own lock of the cache (io/cache/CacheFileLock.cpp): ask it
  // for the written ranges only, unless the user chose (mpirun --mca exports the setting).
  setenv("OMPI_MCA_fs_ufs_lock_algorithm", "3", 0);
  // ROMIO reports a write the disk refused; OMPIO 4.1 does not (mpi/MpiIoChoice.h).
  setMpiIoChoice(mpi::preferRomio());
  session_ = std::make_unique<Session>(argc, argv);
  setWorld(session_->mpi.world());
  // A rank stuck after its write of the cache failed ends the run after 3 s (a failure HDF5
  // returns has stopped every rank by then, with its own line).
  mpi::watchFileErrors(3.0, badInput, [](const char* line) { startStatusRecorder(line); });
}

void noteStopping() {
  mpi::noteStopping();
}

void abortAllRanks(int code) {
  mpi::MpiSession::abortAll(code);
}

#else

struct Launch::Session {};

Launch::Launch(int*, char***, int badInput) {
  const MpiStarter starter = mpiStarter();
  const std::string refusal = refusalWithoutMpi(starter);
  if (refusal.empty()) return;
  if (starter.rank == 0) std::fprintf(stderr, "sphsplat: %s\n", refusal.c_str());
  refusal_ = badInput;
}

void noteStopping() {}

void abortAllRanks(int code) {
  std::_Exit(code);  // unreachable: without MPI no run is in lockstep
}

#endif

Launch::~Launch() = default;

}  // namespace sph::job::distributed
