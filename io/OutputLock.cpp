#include "io/OutputLock.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "io/UserFiles.h"
#include "sim/InputError.h"

namespace sph::io {
namespace {

struct flock wholeFile(short type) {
  struct flock lock {};
  lock.l_type = type;
  lock.l_whence = SEEK_SET;
  return lock;
}

}  // namespace

std::string OutputLock::lockPath(const std::string& path) {
  std::string p = path;
  while (p.size() > 1 && p.back() == '/') p.pop_back();  // "frames/" locks like "frames"
  return siblingPath(p, ".", ".lock");
}

OutputLock OutputLock::acquire(const std::string& path, const std::string& what) {
  OutputLock lock;
  lock.lockPath_ = lockPath(path);
  // A holder that finished unlinks the file while still holding it; a run that opened the old
  // file just before then can lock an orphan. So after locking, the name must still lead to the
  // locked file, else try again with whatever the name leads to now.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(lock.lockPath_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
      throw InputError(path + ": cannot take the " + what + "'s lock " + lock.lockPath_ + " (" +
                       std::strerror(errno) + ")");
    }
    struct flock l = wholeFile(F_WRLCK);
    if (fcntl(fd, F_OFD_SETLK, &l) != 0) {
      const int error = errno;
      ::close(fd);
      if (error == EAGAIN || error == EACCES) {
        throw InputError(path + ": another sphsplat run is writing this " + what +
                         "; wait for it or stop it first");
      }
      throw InputError(path + ": cannot lock the " + what + " (" + std::strerror(error) + ")");
    }
    struct stat held {
    }, named{};
    if (fstat(fd, &held) == 0 && ::stat(lock.lockPath_.c_str(), &named) == 0 &&
        held.st_dev == named.st_dev && held.st_ino == named.st_ino) {
      lock.fd_ = fd;
      return lock;
    }
    ::close(fd);
  }
  throw InputError(path + ": cannot take the " + what + "'s lock " + lock.lockPath_ +
                   " (it keeps being replaced)");
}

bool OutputLock::isHeld(const std::string& path) {
  const int fd = ::open(lockPath(path).c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return false;
  struct flock l = wholeFile(F_WRLCK);
  const bool held = fcntl(fd, F_OFD_GETLK, &l) == 0 && l.l_type != F_UNLCK;
  ::close(fd);
  return held;
}

void OutputLock::release() {
  if (fd_ < 0) return;
  ::unlink(lockPath_.c_str());  // while still holding it: see acquire()
  ::close(fd_);
  fd_ = -1;
}

OutputLock::~OutputLock() {
  release();
}

OutputLock::OutputLock(OutputLock&& other) noexcept
    : fd_(other.fd_), lockPath_(std::move(other.lockPath_)) {
  other.fd_ = -1;
}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = other.fd_;
    lockPath_ = std::move(other.lockPath_);
    other.fd_ = -1;
  }
  return *this;
}

}  // namespace sph::io
