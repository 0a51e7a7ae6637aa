// Files a user names on the command line, read and written without surprises, so that nothing
// is lost (docs/reliability.md, "Bad input is one line and exit 2" and "Nothing is overwritten
// without --overwrite"):
// - an input file (scene, sweep) must be a regular file of at most 64 MiB: a directory, a device
//   such as /dev/zero or a FIFO is refused before anything is read, so nothing reads forever;
// - an output file must be a regular file or not exist yet: a device node, a FIFO or a socket is
//   never replaced, an existing file only with --overwrite, and a file the command reads (the
//   cache being exported, the scene being run) never, whatever path names it (a symlink, a hard
//   link, ./x vs /abs/x: files are compared by device and inode);
// - an output is written under a temporary name in its folder and renamed over PATH once
//   complete, so a failed write (disk full, a kill) never leaves a half-written file.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace sph::io {

constexpr std::uint64_t kMaxInputFileBytes = 64ull << 20;

// The name of a file the program keeps beside `path` (a lock ".NAME.lock", a temporary
// "NAME.partial"): `prefix` + NAME + `suffix` in the same folder, with NAME shortened (its first
// bytes, "~" and a hash of the whole) where the whole would pass the file system's 255-byte
// limit on a name, so that any name a user may choose gets its lock and its temporary.
std::string siblingPath(const std::string& path, const std::string& prefix,
                        const std::string& suffix);

// The whole of `path`; `what` names it in errors ("scene file"). Throws InputError.
std::string readInputFile(const std::string& path, const std::string& what);

// "a directory", "a character device", "a FIFO", ... of an existing path (following symlinks);
// "" for a regular file or a path that does not exist.
std::string nonRegularKind(const std::string& path);
// What is at `path`, said for a refusal to replace it: "" for nothing, "already exists", or for a
// symbolic link that leads nowhere "is a symbolic link to TARGET, which does not exist" or "is a
// symbolic link that loops" (such a link is no file a user would mean to keep, but is not one
// to replace silently either).
std::string whatExists(const std::string& path);

// True when both paths name one existing file (same device and inode).
bool sameFile(const std::string& a, const std::string& b);

// A file an output must not replace, e.g. {"/data/run.h5", "the cache being exported"}.
struct ReadFile {
  std::string path, what;
};

// Throws InputError unless `path` may be written: it is not a directory or another non-regular
// file, it is none of `reads`, and it does not exist unless `overwrite` ("pass --overwrite to
// replace it" otherwise).
void checkOutputPath(const std::string& path, bool overwrite, const std::vector<ReadFile>& reads);

// An output written under a temporary name next to it and renamed over it by commit(). A symlink
// to a regular file is followed, so the file it points at is replaced, not the link.
class AtomicOutput {
 public:
  explicit AtomicOutput(const std::string& path);  // throws InputError naming `path`
  ~AtomicOutput();                                 // removes the temporary unless committed
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  std::FILE* file() { return file_; }
  // Flushes, closes and renames the temporary over the path; throws InputError (disk full, ...).
  void commit();

 private:
  std::string path_, target_, temporary_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

}  // namespace sph::io
