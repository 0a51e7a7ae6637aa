// sphsplat: the command-line program. Sets the process up (standard streams, HDF5, OpenMP, the
// ranks of a distributed run) and hands over to its command line (app/CommandLine.h).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>

#include "app/CommandLine.h"
#include "io/cache/Hdf5.h"
#include "job/ExitCode.h"
#include "job/OpenMpSpinLimit.h"
#include "job/distributed/Launch.h"

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
  if (const int code = sph::job::distributed::runIfStatusRecorder(argc, argv); code >= 0)
    return code;
  sph::job::relaunchWithOpenMpSpinLimit(argv);
  // Under mpirun: one rank of a distributed run (docs/scaling.md); a plain process otherwise.
  const sph::job::distributed::Launch ranks(&argc, &argv, sph::job::kBadInput);
  if (ranks.refusal() >= 0) return ranks.refusal();
  return sph::app::runCommandLine(argc, argv);
}
