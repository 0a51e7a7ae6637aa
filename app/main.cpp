// sphsplat: the command-line program. Sets the process up (standard streams, HDF5, OpenMP, MPI)
// and hands over to its command line (app/CommandLine.h).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include "app/CommandLine.h"
#include "app/MpiStarter.h"
#include "io/cache/Hdf5.h"
#include "job/ExitCode.h"
#include "job/OpenMpSpinLimit.h"
#include "job/distributed/DistributedRun.h"
#include "job/distributed/StatusRecorder.h"
#ifdef SPHSPLAT_MPI
#include "sim/ranks/mpi/FileErrorWatch.h"
#include "sim/ranks/mpi/MpiCommunicator.h"
#include "sim/ranks/mpi/MpiIoChoice.h"
#endif

namespace {

// Started with standard input, output or error closed (`>&-`), the program would give their
// numbers to the first files it opens, the cache's lock and the cache, and a progress line would
// land in the cache: those numbers get /dev/null instead.
void openClosedStandardStreams() {
  for (int fd = 0; fd <= 2; ++fd) {
    if (fcntl(fd, F_GETFD) == -1 && errno == EBADF)
      static_cast<void>(open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY));  // the lowest free: fd
  }
}

}  // namespace

int main(int argc, char** argv) {
  openClosedStandardStreams();
  sph::io::cache::h5::startWithoutExitCleanup();
  // A recorder that rank 0 of an MPI run started (job/distributed/StatusRecorder.h): nothing else
  // of main.
  if (argc == sph::job::distributed::kRecorderArgc &&
      std::strcmp(argv[1], sph::job::distributed::kRecorderArgument) == 0)
    return sph::job::distributed::runStatusRecorder(argv);
  sph::job::relaunchWithOpenMpSpinLimit(argv);
  const sph::app::MpiStarter starter = sph::app::mpiStarter();
#ifdef SPHSPLAT_MPI
  // Under mpirun: the ranks of a distributed run (docs/scaling.md); a plain process otherwise.
  std::optional<sph::ranks::mpi::MpiSession> mpi;
  if (starter.launched) {
    // Open MPI's OMPIO locks the whole file around each write on NFS (its automatic choice),
    // which would wait for ever on the run's own lock of the cache (io/cache/CacheFileLock.cpp):
    // ask it for the written ranges only, unless the user chose (mpirun --mca exports the setting).
    setenv("OMPI_MCA_fs_ufs_lock_algorithm", "3", 0);
    // ROMIO reports a write the disk refused; OMPIO 4.1 does not (sim/ranks/mpi/MpiIoChoice.h).
    sph::job::distributed::setMpiIoChoice(sph::ranks::mpi::preferRomio());
    sph::job::distributed::setWorld(mpi.emplace(&argc, &argv).world());
    // A rank stuck after its write of the cache failed ends the run after 3 s (a failure HDF5
    // returns has stopped every rank by then, with its own line).
    sph::ranks::mpi::watchFileErrors(3.0, sph::job::kBadInput, [](const char* line) {
      sph::job::distributed::startStatusRecorder(line);
    });
  }
#else
  if (const std::string refusal = sph::app::refusalWithoutMpi(starter); !refusal.empty()) {
    if (starter.rank == 0) std::fprintf(stderr, "sphsplat: %s\n", refusal.c_str());
    return sph::job::kBadInput;
  }
#endif
  return sph::app::runCommandLine(argc, argv);
}
