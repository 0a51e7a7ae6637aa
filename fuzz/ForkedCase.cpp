#include "fuzz/ForkedCase.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "app/CommandLine.h"


namespace sph::fuzz {
namespace {

// The child's limit on one allocation (0: none) and the pipe it reports an oversized one on.
std::atomic<std::size_t> allocationLimit{0};
int reportFd = -1;

void checkAllocation(std::size_t size) {
  const std::size_t limit = allocationLimit.load(std::memory_order_relaxed);
  if (limit == 0 || size <= limit) return;
  // Async-signal-safe from here: no allocation, the size as raw bytes, then SIGABRT.
  allocationLimit.store(0);
  if (reportFd >= 0) static_cast<void>(write(reportFd, &size, sizeof size));
  raise(SIGABRT);
}

}  // namespace
}  // namespace sph::fuzz

#if defined(__SANITIZE_ADDRESS__)
// AddressSanitizer owns malloc: its hook sees every allocation once it is made. (Declared here:
// GCC ships no sanitizer/allocator_interface.h, though its runtime has the function.)
extern "C" int __sanitizer_install_malloc_and_free_hooks(
    void (*onMalloc)(const volatile void*, std::size_t), void (*onFree)(const volatile void*));
namespace {
void onMalloc(const volatile void*, std::size_t size) {
  sph::fuzz::checkAllocation(size);
}
void onFree(const volatile void*) {}
const int installed = __sanitizer_install_malloc_and_free_hooks(onMalloc, onFree);
}  // namespace
#else
// Without a sanitizer the harness's own malloc, calloc and realloc (everything in the process
// resolves to them) look at the size and hand over to glibc's.
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);

void* malloc(std::size_t size) {
  sph::fuzz::checkAllocation(size);
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  if (size != 0 && count > static_cast<std::size_t>(-1) / size) return nullptr;
  sph::fuzz::checkAllocation(count * size);
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t size) {
  sph::fuzz::checkAllocation(size);
  return __libc_realloc(p, size);
}
}
#endif

namespace sph::fuzz {

CaseResult runForked(const std::vector<std::string>& args, double timeoutSeconds,
                     std::size_t limit) {
  CaseResult result;
  char errorPath[] = "/tmp/sphsplat-fuzz-stderr-XXXXXX";
  const int errors = mkstemp(errorPath);
  int report[2] = {-1, -1};
  if (errors < 0 || pipe(report) != 0) {
    result.errors = "the harness cannot make a case's files";
    return result;
  }
  unlink(errorPath);
  std::fflush(nullptr);
  const pid_t child = fork();
  if (child == 0) {
    close(report[0]);
    reportFd = report[1];
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(errors, STDERR_FILENO);
    alarm(static_cast<unsigned>(std::max(1.0, timeoutSeconds)));
    std::vector<std::string> words{"sphsplat"};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    allocationLimit.store(limit);
    const int code = app::runCommandLine(static_cast<int>(words.size()), argv.data());
    allocationLimit.store(0);
    std::fflush(nullptr);
    _exit(code);
  }
  close(report[1]);
  int status = 0;
  waitpid(child, &status, 0);
  std::size_t size = 0;
  if (read(report[0], &size, sizeof size) == static_cast<ssize_t>(sizeof size))
    result.oversizedAllocation = size;
  close(report[0]);
  result.exited = WIFEXITED(status);
  result.exitCode = result.exited ? WEXITSTATUS(status) : 0;
  result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  result.timedOut = result.signal == SIGALRM;
  lseek(errors, 0, SEEK_SET);
  char buffer[4096];
  for (ssize_t n; (n = read(errors, buffer, sizeof buffer)) > 0;)
    result.errors.append(buffer, static_cast<std::size_t>(n));
  close(errors);
  return result;
}

std::string verdict(const CaseResult& r, const std::vector<int>& alsoAllowed) {
  if (r.oversizedAllocation > 0)
    return "allocated " + std::to_string(r.oversizedAllocation) + " bytes at once";
  if (r.timedOut) return "hung (stopped by the harness's timeout)";
  if (!r.exited) return std::string("crashed: ") + strsignal(r.signal);
  if (r.errors.find("HDF5-DIAG") != std::string::npos) return "HDF5 printed its error stack";
  if (r.exitCode == 0) return "";
  if (std::find(alsoAllowed.begin(), alsoAllowed.end(), r.exitCode) != alsoAllowed.end())
    return "";
  if (r.exitCode != 2) return "exit " + std::to_string(r.exitCode);
  std::size_t lines = 0;
  for (std::size_t at = 0; (at = r.errors.find("sphsplat: ", at)) != std::string::npos; ++at)
    if (at == 0 || r.errors[at - 1] == '\n') ++lines;
  if (lines != 1) return "exit 2 with " + std::to_string(lines) + " error lines";
  return "";
}

}  // namespace sph::fuzz
