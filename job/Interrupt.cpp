#include "job/Interrupt.h"

#include <cerrno>
#include <csignal>

#include "job/distributed/StatusRecorder.h"

namespace sph::job {
namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void onInterrupt(int signal) {
  const int savedErrno = errno;  // the recorder's start makes system calls
  received = signal;
  // In a frame the ranks write together, rank 0 may never get out of it (mpirun's SIGKILL
  // follows within a second): the recorder writes the status if rank 0 does not.
  job::distributed::startStatusRecorder();
  errno = savedErrno;
}

}  // namespace

void installInterruptHandlers() {
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: HDF5's and stdio's write() calls go on undisturbed. SA_RESETHAND: a second
  // signal takes the default action (terminate) in case the run does not stop soon enough.
  action.sa_flags = SA_RESTART | SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int interruptSignal() {
  return received;
}

const char* signalName(int signal) {
  switch (signal) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    default:
      return "a signal";
  }
}

}  // namespace sph::job
