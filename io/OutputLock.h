// Exclusive ownership of an output path (a cache, a directory of frames) for the life of a run,
// taken before anything is created, truncated or renamed, so that of two runs started at the
// same moment on the same output exactly one proceeds and the other stops with nothing touched
// (exit 2). The lock is an open file description lock (fcntl F_OFD_SETLK) on a hidden file beside
// the output, `.NAME.lock`: the kernel drops it when the process ends however it ends, so a run
// killed with SIGKILL leaves at most an unlocked file behind, which the next run simply takes.
#pragma once

#include <string>

namespace sph::io {

class OutputLock {
 public:
  OutputLock() = default;
  // Locks `path` (which need not exist yet; its directory must). `what` names the output in the
  // message ("cache", "frames directory"). Throws InputError if another process holds it.
  static OutputLock acquire(const std::string& path, const std::string& what);
  // Whether some process holds the lock of `path` now.
  static bool isHeld(const std::string& path);
  // The lock file of `path`.
  static std::string lockPath(const std::string& path);

  ~OutputLock();
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  bool held() const { return fd_ >= 0; }
  void release();

 private:
  int fd_ = -1;
  std::string lockPath_;
};

}  // namespace sph::io
