// Private to io/cache/: an HDF5 file's own bytes, read without HDF5, for the checks of what a
// damaged file could make HDF5 1.10 do (Hdf5Checks.cpp, Hdf5HeapCheck.cpp). HDF5 trusts the
// sizes it reads; these readers check every one against the file before using it. The layouts
// are the HDF5 file format specification's (version 2 object headers: what this project writes);
// a header of another version yields no messages and is left to HDF5.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/cache/Hdf5.h"

namespace sph::io::cache::h5::detail {

// A file read by offset, every read checked against its size.
class RawFile {
 public:
  explicit RawFile(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {
    struct stat st {};
    if (fd_ >= 0 && fstat(fd_, &st) == 0) size_ = static_cast<std::uint64_t>(st.st_size);
  }
  ~RawFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawFile(const RawFile&) = delete;
  RawFile& operator=(const RawFile&) = delete;

  bool open() const { return fd_ >= 0; }
  std::uint64_t size() const { return size_; }
  // The size again (a writer in this process may have grown the file since).
  void refresh() {
    struct stat st {};
    if (fd_ >= 0 && fstat(fd_, &st) == 0) size_ = static_cast<std::uint64_t>(st.st_size);
  }
  // `length` bytes at `offset`, or nothing when they are not all in the file.
  std::optional<std::vector<std::uint8_t>> read(std::uint64_t offset, std::uint64_t length) const {
    if (offset > size_ || length > size_ - offset) return std::nullopt;
    std::vector<std::uint8_t> bytes(length);
    std::uint64_t done = 0;
    while (done < length) {
      const ssize_t r = pread(fd_, bytes.data() + done, length - done,
                              static_cast<off_t>(offset + done));
      if (r <= 0) return std::nullopt;
      done += static_cast<std::uint64_t>(r);
    }
    return bytes;
  }

 private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

inline std::uint64_t little(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

struct Damage {
  std::string what;
};

// One message of an object header: its type and its body's bytes.
struct Message {
  unsigned type = 0, flags = 0;
  const std::uint8_t* body = nullptr;
  std::size_t size = 0;
};

// The messages of the version 2 object header at `address` (an HDF5 address: past the user
// block), its continuation chunks' too; nothing for a header of another version (HDF5 reads
// those itself). Throws Damage when a chunk or a message does not lie in the file.
class HeaderMessages {
 public:
  HeaderMessages(const RawFile& file, std::uint64_t base, std::uint64_t address);
  const std::vector<Message>& messages() const { return messages_; }

 private:
  void scan(const std::vector<std::uint8_t>& chunk, std::size_t p, std::size_t end,
            std::size_t prefixBytes);

  std::vector<std::vector<std::uint8_t>> chunks_;  // (a deque's worth: never reallocated into)
  std::vector<std::pair<std::uint64_t, std::uint64_t>> more_;
  std::vector<Message> messages_;
};

// The file an object is in, opened for the checks, and where HDF5's addresses start in it (past
// the user block). The last one stays open while the same file (by path, device and inode) is
// checked again: a reader checks a header or two per frame, thousands per cache, and opening the
// file and asking HDF5 for its properties each time cost more than the check.
struct FileOf {
  std::shared_ptr<RawFile> raw;
  std::uint64_t base = 0;
};

FileOf fileOf(hid_t object);

}  // namespace sph::io::cache::h5::detail
