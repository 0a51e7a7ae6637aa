#include "io/cache/CacheJournal.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "sim/InputError.h"

namespace sph::io::cache {
namespace {

constexpr char kMagic[8] = {'S', 'P', 'H', 'J', 'R', 'N', 'L', '1'};
constexpr std::size_t kHeaderBytes = 32;

std::uint32_t crc(const void* data, std::size_t n) {
  return static_cast<std::uint32_t>(
      crc32(0L, static_cast<const Bytef*>(data), static_cast<uInt>(n)));
}

bool readAll(int fd, void* out, std::size_t n, std::uint64_t offset) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r =
        pread(fd, static_cast<char*>(out) + done, n - done, static_cast<off_t>(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    done += static_cast<std::size_t>(r);
  }
  return true;
}

bool writeAll(int fd, const void* data, std::size_t n, std::uint64_t offset) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = pwrite(fd, static_cast<const char*>(data) + done, n - done,
                             static_cast<off_t>(offset + done));
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    done += static_cast<std::size_t>(w);
  }
  return true;
}

struct Record {
  std::uint64_t offset = 0, length = 0;
  std::string image;
};

// The journal of the open file `fd`, if it has a whole one.
bool readRecord(int fd, Record& record) {
  unsigned char header[kHeaderBytes];
  if (!readAll(fd, header, kHeaderBytes, 0) || std::memcmp(header, kMagic, 8) != 0) return false;
  std::uint32_t imageCrc = 0, headerCrc = 0;
  std::memcpy(&record.offset, header + 8, 8);
  std::memcpy(&record.length, header + 16, 8);
  std::memcpy(&imageCrc, header + 24, 4);
  std::memcpy(&headerCrc, header + 28, 4);
  if (crc(header, 28) != headerCrc || record.length == 0 || record.length > (1u << 30))
    return false;
  record.image.resize(record.length);
  if (!readAll(fd, record.image.data(), record.length, kHeaderBytes)) return false;
  return crc(record.image.data(), record.image.size()) == imageCrc;
}

}  // namespace

std::uint64_t journalCapacity(std::uint64_t userBlockBytes) {
  return userBlockBytes > kHeaderBytes ? userBlockBytes - kHeaderBytes : 0;
}

bool journalRegion(int fd, std::uint64_t offset, std::uint64_t length,
                   std::uint64_t userBlockBytes) {
  if (length == 0 || length > journalCapacity(userBlockBytes)) return false;
  std::vector<unsigned char> record(kHeaderBytes + length);
  auto failed = [](const char* what) {
    return InputError(std::string(what) + " (" +
                      (errno != 0 ? std::strerror(errno) : "the file ends before it") + ")");
  };
  errno = 0;
  if (!readAll(fd, record.data() + kHeaderBytes, length, offset))
    throw failed("read the root group's header for the journal");
  const std::uint32_t imageCrc = crc(record.data() + kHeaderBytes, length);
  std::memcpy(record.data(), kMagic, 8);
  std::memcpy(record.data() + 8, &offset, 8);
  std::memcpy(record.data() + 16, &length, 8);
  std::memcpy(record.data() + 24, &imageCrc, 4);
  const std::uint32_t headerCrc = crc(record.data(), 28);
  std::memcpy(record.data() + 28, &headerCrc, 4);
  // One write: torn, it fails its CRCs; whole, it describes the state on disk right now.
  errno = 0;
  if (!writeAll(fd, record.data(), record.size(), 0)) throw failed("write the journal");
  return true;
}

bool repairFromJournal(const std::string& path, JournalRepair& repair) {
  Record record;
  {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool ok = readRecord(fd, record);
    repair.replaced.assign(record.length, '\0');
    const bool current = ok && readAll(fd, repair.replaced.data(), record.length, record.offset);
    ::close(fd);
    if (!ok || !current || repair.replaced == record.image) return false;
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    throw InputError(
        path +
        ": a run was killed while committing a frame and left the root group's header torn; "
        "sphsplat restores it from the file's journal but needs write access (" +
        std::strerror(errno) + ")");
  }
  const bool written =
      writeAll(fd, record.image.data(), record.image.size(), record.offset) && fsync(fd) == 0;
  ::close(fd);
  if (!written)
    throw InputError(path + ": cannot write the repaired root group header (" +
                     std::strerror(errno) + ")");
  repair.path = path;
  repair.offset = record.offset;
  return true;
}

void undoRepair(const JournalRepair& repair) {
  const int fd = ::open(repair.path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return;
  writeAll(fd, repair.replaced.data(), repair.replaced.size(), repair.offset);
  ::close(fd);
}

}  // namespace sph::io::cache
