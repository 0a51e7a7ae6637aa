#include "io/UserFiles.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "io/MessageText.h"
#include "sim/InputError.h"

namespace sph::io {
namespace {

std::string kindOf(mode_t mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string systemError() {
  return std::strerror(errno);
}

}  // namespace

std::string nonRegularKind(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return "";
  return kindOf(st.st_mode);
}

bool sameFile(const std::string& a, const std::string& b) {
  struct stat sa {
  }, sb{};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
         sa.st_ino == sb.st_ino;
}

std::string readInputFile(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(path + ": cannot open the " + what + " (" + systemError() + ")");
  auto check = [&](const struct stat& s) {
    if (S_ISDIR(s.st_mode)) throw InputError(path + ": is a directory; expected a " + what);
    if (!S_ISREG(s.st_mode)) {
      throw InputError(path + ": is " + kindOf(s.st_mode) + ", not a regular file; expected a " +
                       what);
    }
    if (static_cast<std::uint64_t>(s.st_size) > kMaxInputFileBytes) {
      throw InputError(path + ": " + readableNumber(static_cast<double>(s.st_size) / 1048576, 3) +
                       " MiB is too large for a " + what + " (at most " +
                       std::to_string(kMaxInputFileBytes >> 20) + " MiB)");
    }
  };
  check(st);
  // Non-blocking: a FIFO put in the file's place after stat() must not hang the open.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(path + ": cannot open the " + what + " (" + systemError() + ")");
  std::string text;
  try {
    if (::fstat(fd, &st) != 0)
      throw InputError(path + ": cannot read the " + what + " (" + systemError() + ")");
    check(st);
    text.resize(static_cast<std::size_t>(st.st_size));
    std::size_t got = 0;
    char extra = 0;
    for (;;) {
      // Read one byte past the size stat() gave: a file that grew meanwhile is still capped.
      char* into = got < text.size() ? &text[got] : &extra;
      const std::size_t room = got < text.size() ? text.size() - got : 1;
      const ssize_t n = ::read(fd, into, room);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw InputError(path + ": cannot read the " + what + " (" + systemError() + ")");
      if (n == 0) break;
      if (into == &extra) {
        throw InputError(path + ": changed while it was read (it grew); expected a " + what +
                         " that stays as it is");
      }
      got += static_cast<std::size_t>(n);
    }
    text.resize(got);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  return text;
}

std::string whatExists(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return "";
  if (!S_ISLNK(st.st_mode) || ::stat(path.c_str(), &st) == 0) return "already exists";
  if (errno == ELOOP) return "is a symbolic link that loops";
  char target[4096];
  const ssize_t n = ::readlink(path.c_str(), target, sizeof target - 1);
  const std::string to = n > 0 ? std::string(target, static_cast<std::size_t>(n)) : "?";
  return "is a symbolic link to " + printablePath(to) + ", which does not exist";
}

void checkOutputPath(const std::string& path, bool overwrite, const std::vector<ReadFile>& reads) {
  for (const ReadFile& r : reads) {
    if (sameFile(path, r.path)) {
      throw InputError(path + ": is " + r.what + " (" + r.path +
                       "); refusing to write over it, even with --overwrite");
    }
  }
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return;  // a new file
  const std::string kind = nonRegularKind(path);
  if (!kind.empty()) {
    throw InputError(path + ": is " + kind +
                     ", not a regular file; refusing to replace it (choose a file name)");
  }
  if (!overwrite)
    throw InputError(path + ": " + whatExists(path) + "; pass --overwrite to replace it");
}

std::string siblingPath(const std::string& path, const std::string& prefix,
                        const std::string& suffix) {
  constexpr std::size_t kMostNameBytes = 255;  // NAME_MAX of Linux's file systems
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (prefix.size() + name.size() + suffix.size() > kMostNameBytes) {
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a of the whole name
    for (const unsigned char c : name) hash = (hash ^ c) * 1099511628211ull;
    char tail[24];
    std::snprintf(tail, sizeof tail, "~%016llx", static_cast<unsigned long long>(hash));
    std::size_t keep = kMostNameBytes - prefix.size() - suffix.size() - std::strlen(tail);
    // Not inside a UTF-8 character.
    while (keep > 0 && (static_cast<unsigned char>(name[keep]) & 0xc0) == 0x80) --keep;
    name = name.substr(0, keep) + tail;
  }
  return dir + prefix + name + suffix;
}

AtomicOutput::AtomicOutput(const std::string& path) : path_(path), target_(path) {
  // Replace what a symlink points at, not the link (a dangling link is replaced itself).
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
    char resolved[PATH_MAX];
    if (::realpath(path.c_str(), resolved)) target_ = resolved;
  }
  std::string pattern = siblingPath(target_, "", ".partial-XXXXXX");
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) throw InputError(path + ": cannot create the file (" + systemError() + ")");
  temporary_ = pattern;
  // mkstemp makes the file 0600; give it the mode a plain fopen() would have.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  file_ = ::fdopen(fd, "w");
  if (!file_) {
    ::close(fd);
    ::unlink(temporary_.c_str());
    throw InputError(path + ": cannot create the file (" + systemError() + ")");
  }
}

AtomicOutput::~AtomicOutput() {
  if (file_) std::fclose(file_);
  if (!committed_ && !temporary_.empty()) ::unlink(temporary_.c_str());
}

void AtomicOutput::commit() {
  errno = 0;
  const bool flushFailed = std::fflush(file_) != 0;
  const int error = errno;  // a stream that failed earlier fails its flush again, with the cause
  const bool failed = flushFailed || std::ferror(file_) != 0;
  const bool closeFailed = std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed || closeFailed) {
    const int cause = failed ? error : errno;
    throw InputError(path_ + ": cannot write the file (" +
                     (cause ? std::strerror(cause) : "write error") +
                     "); nothing was written to it");
  }
  if (::rename(temporary_.c_str(), target_.c_str()) != 0)
    throw InputError(path_ + ": cannot write the file (" + systemError() + ")");
  committed_ = true;
}

}  // namespace sph::io
