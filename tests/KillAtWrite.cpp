// A preload library for the crash tests (tests/test_cache_crash.cpp): it counts the calls that
// change a cache on disk (write, pwrite, pwritev, ftruncate on a file whose name ends in ".h5",
// ".h5.partial", ".xdmf" or ".xdmf.tmp") and, when SPHSPLAT_KILL_AT_WRITE=N is set, sends the
// process SIGKILL just before the N-th. A process can only be killed between two system calls,
// so running a command once for each N visits every state its kill -9 could leave the file in.
// SPHSPLAT_TEAR_AT_WRITE=N instead performs the N-th write only up to its first page boundary
// (SPHSPLAT_TEAR_KEEP=first) or its last one (=last) and then kills: what Linux does when SIGKILL
// arrives while a write spanning pages is being copied.
// SPHSPLAT_FAIL_AT_WRITE=N makes the N-th call fail instead, as a full disk does: it returns -1
// with errno ENOSPC and changes nothing; the calls after it succeed again.
// SPHSPLAT_WRITE_COUNT_FILE=PATH receives the number of such calls when the process exits, and
// SPHSPLAT_WRITE_LOG=PATH one line per call: its number, bytes and file offset.
// SPHSPLAT_COUNT_ONLY=SUFFIX counts (and so kills, tears, fails and logs at) only the calls on
// files whose name ends in SUFFIX (".partial": a new cache before its frame 0 is published).
// SPHSPLAT_READER_VIEW_LOG=PATH checks what a reader opening the cache between two calls would
// meet (ReaderView.h).
#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tests/ReaderView.h"

namespace {

long counted = 0;

// The file behind `fd` if it is a cache or its sidecar (by name), else "".
std::string cachePath(int fd) {
  char link[64], path[4096];
  std::snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, path, sizeof path - 1);
  if (n <= 0) return "";
  path[n] = '\0';
  const std::size_t len = static_cast<std::size_t>(n);
  auto endsWith = [&](const char* suffix) {
    const std::size_t s = std::strlen(suffix);
    return len >= s && std::strcmp(path + len - s, suffix) == 0;
  };
  const bool cache =
      endsWith(".h5") || endsWith(".h5.partial") || endsWith(".xdmf") || endsWith(".xdmf.tmp");
  return cache ? path : "";
}

long envNumber(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::atol(v) : 0L;
}

// What beforeChange() returns for a call to fail with ENOSPC (SPHSPLAT_FAIL_AT_WRITE).
constexpr long kFail = -2;

// Called before each file-changing call on `fd` of `bytes` at `offset` (-1: the file position).
// Returns how many bytes to write before dying when this call is to be torn, kFail when it is to
// fail, else -1.
long beforeChange(int fd, std::size_t bytes, long long offset, const void* data = nullptr) {
  const std::string path = cachePath(fd);
  if (path.empty()) return -1;
  static const std::string only =
      std::getenv("SPHSPLAT_COUNT_ONLY") ? std::getenv("SPHSPLAT_COUNT_ONLY") : "";
  if (path.size() < only.size() || path.compare(path.size() - only.size(), only.size(), only) != 0)
    return -1;
  ++counted;
  static const long killAt = envNumber("SPHSPLAT_KILL_AT_WRITE");
  static const long tearAt = envNumber("SPHSPLAT_TEAR_AT_WRITE");
  static const long failAt = envNumber("SPHSPLAT_FAIL_AT_WRITE");
  if (offset < 0) offset = lseek(fd, 0, SEEK_CUR);
  if (const char* log = std::getenv("SPHSPLAT_WRITE_LOG")) {
    if (std::FILE* f = std::fopen(log, "a")) {
      std::fprintf(f, "%ld %zu %lld\n", counted, bytes, offset);
      std::fclose(f);
    }
  }
  if (data) sph::test::readerview::beforeWrite(path.c_str(), fd, data, bytes, offset, counted);
  if (killAt > 0 && counted == killAt) raise(SIGKILL);
  if (failAt > 0 && counted == failAt) return kFail;
  if (tearAt > 0 && counted == tearAt) {
    const long long page = 4096, end = offset + static_cast<long long>(bytes);
    const char* keep = std::getenv("SPHSPLAT_TEAR_KEEP");
    long long cut = (offset / page + 1) * page;  // first boundary
    if (keep && std::strcmp(keep, "last") == 0)
      cut = std::max(cut, (end - 1) / page * page);  // last one
    return static_cast<long>(std::min(end, cut) - offset);
  }
  return -1;
}

// After a call has changed the file behind `fd`.
void afterChange(int fd) {
  const std::string path = cachePath(fd);
  if (!path.empty()) sph::test::readerview::afterChange(path.c_str(), fd, counted);
}

// A call that fails as on a full disk.
ssize_t full() {
  errno = ENOSPC;
  return -1;
}

template <class F>
F next(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

struct CountReport {
  ~CountReport() {
    const char* path = std::getenv("SPHSPLAT_WRITE_COUNT_FILE");
    if (!path) return;
    if (std::FILE* f = std::fopen(path, "w")) {
      std::fprintf(f, "%ld\n", counted);
      std::fclose(f);
    }
  }
} report;

}  // namespace

extern "C" {

ssize_t write(int fd, const void* buf, size_t n) {
  static auto real = next<ssize_t (*)(int, const void*, size_t)>("write");
  const long tear = beforeChange(fd, n, -1, buf);
  if (tear == kFail) return full();
  if (tear < 0) {
    const ssize_t r = real(fd, buf, n);
    afterChange(fd);
    return r;
  }
  real(fd, buf, static_cast<size_t>(tear));
  raise(SIGKILL);
  return -1;
}

ssize_t pwrite(int fd, const void* buf, size_t n, off_t offset) {
  static auto real = next<ssize_t (*)(int, const void*, size_t, off_t)>("pwrite");
  const long tear = beforeChange(fd, n, offset, buf);
  if (tear == kFail) return full();
  if (tear < 0) {
    const ssize_t r = real(fd, buf, n, offset);
    afterChange(fd);
    return r;
  }
  real(fd, buf, static_cast<size_t>(tear), offset);
  raise(SIGKILL);
  return -1;
}

ssize_t pwrite64(int fd, const void* buf, size_t n, off64_t offset) {
  static auto real = next<ssize_t (*)(int, const void*, size_t, off64_t)>("pwrite64");
  const long tear = beforeChange(fd, n, offset, buf);
  if (tear == kFail) return full();
  if (tear < 0) {
    const ssize_t r = real(fd, buf, n, offset);
    afterChange(fd);
    return r;
  }
  real(fd, buf, static_cast<size_t>(tear), offset);
  raise(SIGKILL);
  return -1;
}

ssize_t pwritev(int fd, const struct iovec* iov, int count, off_t offset) {
  static auto real = next<ssize_t (*)(int, const struct iovec*, int, off_t)>("pwritev");
  std::size_t n = 0;
  for (int i = 0; i < count; ++i) n += iov[i].iov_len;
  const long tear = beforeChange(fd, n, offset);
  if (tear == kFail) return full();
  if (tear >= 0) raise(SIGKILL);  // HDF5's sec2 driver does not use it
  const ssize_t r = real(fd, iov, count, offset);
  afterChange(fd);
  return r;
}

int ftruncate(int fd, off_t length) {
  static auto real = next<int (*)(int, off_t)>("ftruncate");
  const long tear = beforeChange(fd, 0, 0);
  if (tear == kFail) return static_cast<int>(full());
  const int r = real(fd, length);
  if (tear >= 0) raise(SIGKILL);
  afterChange(fd);
  return r;
}

int ftruncate64(int fd, off64_t length) {
  static auto real = next<int (*)(int, off64_t)>("ftruncate64");
  const long tear = beforeChange(fd, 0, 0);
  if (tear == kFail) return static_cast<int>(full());
  const int r = real(fd, length);
  if (tear >= 0) raise(SIGKILL);
  afterChange(fd);
  return r;
}

}  // extern "C"
