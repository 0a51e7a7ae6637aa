#include "app/StatusRecorder.h"

#include <fcntl.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <thread>

#include "io/CacheSession.h"
#include "sim/InputError.h"

namespace sph::app {
namespace {

// Everything the signal handler needs, prepared beforehand: fork and exec only copy it.
constexpr std::size_t kTextBytes = 4096;
char gExe[] = "/proc/self/exe";
char gArgument[64];
char gCache[kTextBytes];
char gReason[kTextBytes];
char* gArgv[] = {gExe, gArgument, gCache, gReason, nullptr};
volatile std::sig_atomic_t gArmed = 0, gStarted = 0;
int gPipe[2] = {-1, -1};  // read end: the recorder's descriptor 3; write end: rank 0's

void copy(char* to, const std::string& from) {
  const std::size_t n = std::min(from.size(), kTextBytes - 1);
  std::memcpy(to, from.data(), n);
  to[n] = '\0';
}

// How long the recorder waits after rank 0 has gone: mpirun ends the other ranks with SIGTERM
// and, 1 s later, SIGKILL (Open MPI's odls_base_sigkill_timeout), so none writes after that.
constexpr double kGraceSeconds = 2.0;

}  // namespace

int runStatusRecorder(char** argv) {
  std::signal(SIGPIPE, SIG_IGN);  // mpirun, whose pipes stdout and stderr were, may be gone
  // Until rank 0 has exited (the write end closes), or it says it recorded the status itself.
  char byte = 0;
  ssize_t got = 0;
  while ((got = read(3, &byte, 1)) < 0 && errno == EINTR) {
  }
  if (got != 0) return got == 1 ? 0 : 2;  // recorded by rank 0, or no pipe from rank 0 at all
  std::this_thread::sleep_for(std::chrono::duration<double>(kGraceSeconds));
  try {
    io::CacheSession::recordStop(argv[2], argv[3]);
  } catch (const std::exception&) {
    return 2;  // the cache keeps "running" with no run holding it: `info` reads it as killed
  }
  return 0;
}

void armStatusRecorder(const std::string& cache, const std::string& reason) {
  if (!cache.empty() && gPipe[1] < 0) {
    if (pipe2(gPipe, O_CLOEXEC) != 0) gPipe[0] = gPipe[1] = -1;
  }
  copy(gArgument, kRecorderArgument);
  copy(gCache, cache);
  copy(gReason, reason);
  gArmed = 1;
}

void disarmStatusRecorder() {
  gArmed = 0;
}

bool statusRecorderArmed() {
  return gArmed != 0;
}

void startStatusRecorder(const char* reason) {
  if (!gArmed || gStarted || gCache[0] == '\0' || gPipe[0] < 0) return;
  gStarted = 1;
  if (reason) copy(gReason, reason);
  // vfork: no atfork handlers (MPI's) and nothing copied; the child only makes system calls.
  const pid_t pid = vfork();
  if (pid == 0) {
    setsid();  // out of rank 0's process group, which mpirun's SIGKILL reaches
    if (gPipe[0] == 3)
      fcntl(3, F_SETFD, 0);  // keep it across exec
    else
      dup2(gPipe[0], 3);
    for (int fd = 4; fd < 1024; ++fd) close(fd);
    const int null = open("/dev/null", O_RDWR);
    if (null >= 0) dup2(null, 0), dup2(null, 1), dup2(null, 2);
    execv(gExe, gArgv);
    _exit(127);
  }
}

void cancelStatusRecorder() {
  if (!gStarted || gPipe[1] < 0) return;
  const char done = 'd';
  (void)!write(gPipe[1], &done, 1);
}

}  // namespace sph::app
