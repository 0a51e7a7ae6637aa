#include "io/cache/CacheFileLock.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "sim/InputError.h"

namespace sph::io::cache {
namespace {

// The lock covers one byte far past any data the file will hold, not the whole file: MPI-IO
// takes POSIX byte-range locks on the cache's data while the ranks write a frame together (ROMIO
// around its read-modify-write of a collective write's holes, and every write on NFS), and POSIX
// and open file description locks on overlapping ranges conflict even within one process: a
// whole-file lock made rank 0's own ROMIO lock wait forever. (Open MPI's OMPIO on NFS locks the
// entire file for each write, which no lock on the cache can stay clear of: docs/cache-format.md,
// "Crash safety" point 5.) Readers probe the same byte; a whole-file probe (an older sphsplat)
// still sees it, and this probe still sees an older run's whole-file lock.
constexpr off_t kSentinelByte = off_t{1} << 62;

struct flock sentinel() {
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  lock.l_start = kSentinelByte;
  lock.l_len = 1;
  return lock;
}

}  // namespace

int lockCacheFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0)
    throw InputError(path + ": cannot open the cache for writing (" + std::strerror(errno) + ")");
  struct flock lock = sentinel();
  if (fcntl(fd, F_OFD_SETLK, &lock) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EAGAIN || error == EACCES) {
      throw InputError(
          path + ": another sphsplat run is writing this cache; wait for it or stop it first");
    }
    throw InputError(path + ": cannot lock the cache (" + std::strerror(error) + ")");
  }
  return fd;
}

bool cacheIsLocked(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  struct flock lock = sentinel();
  const bool locked = fcntl(fd, F_OFD_GETLK, &lock) == 0 && lock.l_type != F_UNLCK;
  ::close(fd);
  return locked;
}

}  // namespace sph::io::cache
