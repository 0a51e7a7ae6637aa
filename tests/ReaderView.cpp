#include "tests/ReaderView.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

namespace sph::test::readerview {
namespace {

// What the checker knows of one file: a copy of its bytes as the writer left them, and the end of
// the file (as its superblock says) when the root header last changed: what a reader can reach.
struct Shadow {
  std::string bytes;
  std::size_t committedEnd = 0;
};

const char* logPath() {
  static const char* path = std::getenv("SPHSPLAT_READER_VIEW_LOG");
  return path;
}

bool published(const char* path) {
  const std::size_t n = std::strlen(path);
  return n > 3 && std::strcmp(path + n - 3, ".h5") == 0;
}

void report(long call, const std::string& what) {
  if (std::FILE* f = std::fopen(logPath(), "a")) {
    std::fprintf(f, "after call %ld: %s\n", call, what.c_str());
    std::fclose(f);
  }
}

std::uint64_t little(const std::string& s, std::size_t at, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < bytes && at + i < s.size(); ++i)
    v |= static_cast<std::uint64_t>(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return v;
}

// Where HDF5 would find the superblock: at 0, 512, 1024, ... (after the user block).
bool superblock(const std::string& s, std::size_t& at) {
  static const char signature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  for (at = 0; at + 48 <= s.size(); at = at == 0 ? 512 : 2 * at) {
    if (std::memcmp(s.data() + at, signature, 8) == 0) return s[at + 8] >= 2;  // version 2 or 3
  }
  return false;
}

// HDF5's end-of-file address as the superblock records it, a file offset (0 if there is none).
std::size_t endOfFile(const std::string& s) {
  std::size_t base = 0;
  return superblock(s, base) ? little(s, base + 28, 8) : 0;
}

// The regions a commit may change in place: the user block, the superblock and the root group's
// object header (version 2: "OHDR", version, flags, optional times and phase change values, the
// size of its one chunk, the chunk, a checksum).
struct Mutable {
  std::size_t base = 0, rootStart = 0, rootEnd = 0;
  bool contains(std::size_t offset) const {
    return offset < base + 48 || (offset >= rootStart && offset < rootEnd);
  }
};

bool mutableRegions(const std::string& s, Mutable& m) {
  if (!superblock(s, m.base)) return false;
  const std::size_t root = m.base + little(s, m.base + 36, 8);
  if (root + 6 > s.size() || s.compare(root, 4, "OHDR") != 0) return false;
  const unsigned flags = static_cast<unsigned char>(s[root + 5]);
  std::size_t at = root + 6 + ((flags & 0x20) ? 16 : 0) + ((flags & 0x10) ? 4 : 0);
  const std::size_t sizeBytes = std::size_t(1) << (flags & 3);
  m.rootStart = root;
  m.rootEnd = at + sizeBytes + little(s, at, sizeBytes) + 4;
  return true;
}

Shadow& shadowOf(const char* path, int fd) {
  static std::map<std::string, Shadow> shadows;
  auto [it, fresh] = shadows.try_emplace(path);
  if (fresh) {
    // First sight of this file under this name (a resumed cache, or one just published):
    // everything in it is committed.
    struct stat st {};
    if (fstat(fd, &st) == 0) {
      it->second.bytes.resize(static_cast<std::size_t>(st.st_size));
      const int in = ::open(path, O_RDONLY | O_CLOEXEC);
      if (in >= 0) {
        std::size_t done = 0;
        while (done < it->second.bytes.size()) {
          const ssize_t r = pread(in, &it->second.bytes[done], it->second.bytes.size() - done,
                                  static_cast<off_t>(done));
          if (r <= 0) break;
          done += static_cast<std::size_t>(r);
        }
        ::close(in);
      }
      it->second.committedEnd = endOfFile(it->second.bytes);
    }
  }
  return it->second;
}

}  // namespace

void beforeWrite(const char* path, int fd, const void* data, std::size_t bytes, long long offset,
                 long call) {
  if (!logPath() || !published(path) || offset < 0) return;
  Shadow& shadow = shadowOf(path, fd);
  const auto at = static_cast<std::size_t>(offset);
  const auto* in = static_cast<const char*>(data);
  Mutable regions;
  const bool known = mutableRegions(shadow.bytes, regions);
  std::size_t first = SIZE_MAX, last = 0;
  for (std::size_t i = 0; i < bytes && at + i < shadow.committedEnd; ++i) {
    if (in[i] == shadow.bytes[at + i] || (known && regions.contains(at + i))) continue;
    first = std::min(first, at + i), last = at + i;
  }
  if (first != SIZE_MAX) {
    report(call, "changes bytes " + std::to_string(first) + "-" + std::to_string(last) +
                     " of a linked object in place (the file was " +
                     std::to_string(shadow.committedEnd) + " bytes at the last commit)");
  }
  if (shadow.bytes.size() < at + bytes) shadow.bytes.resize(at + bytes, '\0');
  shadow.bytes.replace(at, bytes, in, bytes);
  // The root header rewritten: what its new links point to is below the superblock's end of file
  // (written by the commit's first flush) and reachable from now on.
  if (known && at <= regions.rootStart && at + bytes > regions.rootStart)
    shadow.committedEnd = std::max(shadow.committedEnd, endOfFile(shadow.bytes));
}

void afterChange(const char* path, int fd, long call) {
  if (!logPath() || !published(path)) return;
  struct stat st {};
  if (fstat(fd, &st) != 0) return;
  Shadow& shadow = shadowOf(path, fd);
  shadow.bytes.resize(static_cast<std::size_t>(st.st_size), '\0');
  const std::uint64_t end = endOfFile(shadow.bytes);
  if (static_cast<std::uint64_t>(st.st_size) < end) {
    report(call, "the file has " + std::to_string(st.st_size) + " bytes, its superblock says " +
                     std::to_string(end) + " (a reader opening it now: \"truncated file\")");
  }
}

}  // namespace sph::test::readerview
