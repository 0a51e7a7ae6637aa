#include "job/distributed/StatusRecorder.h"

#include <fcntl.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "io/cache/CacheSession.h"
#include "sim/InputError.h"

namespace sph::job::distributed {
namespace {

// Everything the signal handler needs, prepared beforehand: fork and exec only copy it.
constexpr std::size_t kTextBytes = 4096;
char gExe[] = "/proc/self/exe";
char gArgument[64];
char gCache[kTextBytes];
char gReason[kTextBytes];
char gLauncher[32];   // rank 0's parent (mpirun or its daemon), which exits after every rank
char gMaxFrames[32];  // frames the cache may hold: those committed before this frame, plus it
char* gArgv[] = {gExe, gArgument, gCache, gReason, gLauncher, gMaxFrames, nullptr};
volatile std::sig_atomic_t gArmed = 0;
// Both the main thread (its own failure) and the file-error watch's thread may start it.
std::atomic<int> gStarted{0};
static_assert(std::atomic<int>::is_always_lock_free, "used from a signal handler");
int gPipe[2] = {-1, -1};  // read end: the recorder's descriptor 3; write end: rank 0's

void copy(char* to, const std::string& from) {
  const std::size_t n = std::min(from.size(), kTextBytes - 1);
  std::memcpy(to, from.data(), n);
  to[n] = '\0';
}

// How long the recorder waits for the launcher to exit after rank 0 has gone: mpirun ends the
// other ranks with SIGTERM and, 1 s later, SIGKILL (Open MPI's odls_base_sigkill_timeout), and
// exits once they have; no rank writes after that. Past this bound it records all the same.
constexpr double kLauncherWaitSeconds = 60.0;

}  // namespace

int runStatusRecorder(char** argv) {
  // Started from a signal handler, whose signal stays blocked across exec: take it back.
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  std::signal(SIGPIPE, SIG_IGN);  // mpirun, whose pipes stdout and stderr were, may be gone
  // Until rank 0 has exited (the write end closes), or it says it recorded the status itself.
  char byte = 0;
  ssize_t got = 0;
  while ((got = read(3, &byte, 1)) < 0 && errno == EINTR) {
  }
  if (got != 0) return got == 1 ? 0 : 2;  // recorded by rank 0, or no pipe from rank 0 at all
  // Until the launcher has exited too: then no other rank writes to the cache any more.
  const auto launcher = static_cast<pid_t>(std::atoll(argv[4]));
  const auto start = std::chrono::steady_clock::now();
  while (launcher > 1 && kill(launcher, 0) == 0 &&
         std::chrono::steady_clock::now() - start <
             std::chrono::duration<double>(kLauncherWaitSeconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  try {
    io::cache::CacheSession::recordStop(argv[2], argv[3], std::strtoull(argv[5], nullptr, 10));
  } catch (const std::exception&) {
    return 2;  // the cache keeps "running" with no run holding it: `info` reads it as killed
  }
  return 0;
}

void armStatusRecorder(const std::string& cache, const std::string& reason,
                       std::uint64_t maxFrames) {
  if (!cache.empty() && gPipe[1] < 0) {
    if (pipe2(gPipe, O_CLOEXEC) != 0) gPipe[0] = gPipe[1] = -1;
  }
  copy(gArgument, kRecorderArgument);
  copy(gCache, cache);
  copy(gReason, reason);
  copy(gLauncher, std::to_string(getppid()));
  copy(gMaxFrames, std::to_string(maxFrames));
  // The texts are in place before a signal handler may see the recorder armed.
  std::atomic_signal_fence(std::memory_order_release);
  gArmed = 1;
}

void disarmStatusRecorder() {
  gArmed = 0;
}

bool statusRecorderArmed() {
  return gArmed != 0;
}

void startStatusRecorder(const char* reason) {
  if (!gArmed || gCache[0] == '\0' || gPipe[0] < 0 || gStarted.exchange(1) != 0) return;
  if (reason) copy(gReason, reason);
  // vfork: no atfork handlers (MPI's) and nothing copied; the child only makes system calls.
  const pid_t pid = vfork();
  if (pid == 0) {
    setsid();  // out of rank 0's process group, which mpirun's SIGKILL reaches
    if (gPipe[0] == 3)
      fcntl(3, F_SETFD, 0);  // keep it across exec
    else
      dup2(gPipe[0], 3);
    // Nothing of rank 0's (its MPI sockets) may stay open in the recorder.
    if (close_range(4, ~0U, 0) != 0)
      for (int fd = 4; fd < 1024; ++fd) close(fd);
    const int null = open("/dev/null", O_RDWR);
    if (null >= 0) dup2(null, 0), dup2(null, 1), dup2(null, 2);
    execv(gExe, gArgv);
    _exit(127);
  }
}

void cancelStatusRecorder() {
  if (!gStarted.load() || gPipe[1] < 0) return;
  const char done = 'd';
  (void)!write(gPipe[1], &done, 1);
}

}  // namespace sph::job::distributed
