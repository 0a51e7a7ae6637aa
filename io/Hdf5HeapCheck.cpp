// The check of a variable-length string's global heap object before HDF5 reads it (Hdf5.h,
// checkHeapString). HDF5 1.10 copies a heap object by the size the heap records into a buffer
// sized by the length the attribute records, and walks a heap collection by the sizes of its
// objects without bounds: one changed byte in either makes it read or write past its buffers.
// Global heap collections carry no checksum (the object headers around them do), so the check
// reads them here, from the file, by the HDF5 file format specification (version 2 object
// headers, version 3 attribute messages: what this project writes); a layout it does not know is
// left to HDF5.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "io/Hdf5.h"

namespace sph::io::h5 {
namespace {

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

std::uint64_t little(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

// Where a variable-length string attribute's value points: its length and heap object.
struct HeapReference {
  std::uint64_t length = 0, collection = 0;
  std::uint32_t index = 0;
};

struct Damage {
  std::string what;
};

// The messages of one chunk of a version 2 object header ([begin, end) of `chunk`): looks for the
// attribute `name`, collects continuation chunks.
std::optional<HeapReference> scanMessages(const std::vector<std::uint8_t>& chunk, std::size_t begin,
                                          std::size_t end, bool creationOrder,
                                          const std::string& name,
                                          std::vector<std::pair<std::uint64_t, std::uint64_t>>& more,
                                          bool& unknown) {
  const std::size_t prefix = creationOrder ? 6 : 4;
  std::size_t p = begin;
  while (p + prefix <= end) {
    const unsigned type = chunk[p];
    const std::size_t size = little(&chunk[p + 1], 2);
    const std::size_t body = p + prefix;
    if (body + size > end) throw Damage{"a message of its object header runs past its chunk"};
    if (type == 0x10 && size >= 16) {  // continuation: offset and length of the next chunk
      more.emplace_back(little(&chunk[body], 8), little(&chunk[body + 8], 8));
    } else if (type == 0x0C && size >= 8) {  // attribute
      const unsigned version = chunk[body], flags = chunk[body + 1];
      const std::size_t nameSize = little(&chunk[body + 2], 2);
      const std::size_t typeSize = little(&chunk[body + 4], 2);
      const std::size_t spaceSize = little(&chunk[body + 6], 2);
      const std::size_t nameAt = body + (version == 3 ? 9 : 8);
      if (version < 2 || flags != 0) {
        // Padded (version 1) or shared parts: a layout this project does not write.
        if (nameAt + nameSize <= body + size &&
            std::string(reinterpret_cast<const char*>(&chunk[nameAt]),
                        nameSize > 0 ? nameSize - 1 : 0) == name)
          unknown = true;
      } else if (nameAt + nameSize + typeSize + spaceSize + 16 <= body + size && nameSize > 0 &&
                 std::string(reinterpret_cast<const char*>(&chunk[nameAt]), nameSize - 1) == name) {
        const std::size_t typeAt = nameAt + nameSize;
        const unsigned typeClass = chunk[typeAt] & 0x0F, kind = chunk[typeAt + 1] & 0x0F;
        if (typeClass != 9 || kind != 1) {
          unknown = true;  // not a variable-length string: nothing of the heap's is read
          return std::nullopt;
        }
        const std::size_t data = typeAt + typeSize + spaceSize;
        HeapReference r;
        r.length = little(&chunk[data], 4);
        r.collection = little(&chunk[data + 4], 8);
        r.index = static_cast<std::uint32_t>(little(&chunk[data + 12], 4));
        return r;
      }
    }
    p = body + size;
  }
  return std::nullopt;
}

// The attribute's heap reference, read from the object header at `header` (an HDF5 address).
std::optional<HeapReference> findReference(const RawFile& file, std::uint64_t base,
                                           std::uint64_t header, const std::string& name) {
  const auto start = file.read(base + header, 16);
  if (!start || std::memcmp(start->data(), "OHDR", 4) != 0 || (*start)[4] != 2)
    return std::nullopt;  // version 1 headers and anything else: HDF5's own reading
  const unsigned flags = (*start)[5];
  std::size_t at = 6;
  if (flags & 0x20) at += 16;  // access, modification, change and birth times
  if (flags & 0x10) at += 4;   // attribute phase change values
  const std::size_t sizeBytes = std::size_t{1} << (flags & 0x03);
  const auto prefix = file.read(base + header, at + sizeBytes);
  if (!prefix) throw Damage{"its object header runs past the end of the file"};
  const std::uint64_t chunkSize = little(&(*prefix)[at], static_cast<int>(sizeBytes));
  const auto chunk = file.read(base + header, at + sizeBytes + chunkSize);
  if (!chunk) throw Damage{"its object header runs past the end of the file"};
  std::vector<std::pair<std::uint64_t, std::uint64_t>> more;
  bool unknown = false;
  const bool creationOrder = (flags & 0x04) != 0;
  auto found = scanMessages(*chunk, at + sizeBytes, chunk->size(), creationOrder, name, more,
                            unknown);
  for (std::size_t i = 0; !found && !unknown && i < more.size() && i < 1024; ++i) {
    const auto next = file.read(base + more[i].first, more[i].second);
    if (!next || next->size() < 8 || std::memcmp(next->data(), "OCHK", 4) != 0)
      throw Damage{"a continuation of its object header lies outside the file"};
    found = scanMessages(*next, 4, next->size() - 4, creationOrder, name, more, unknown);
  }
  return found;
}

// Walks the heap collection at `collection` as HDF5 loads it and checks the object `r` points to.
void checkCollection(const RawFile& file, std::uint64_t base, const HeapReference& r) {
  const auto head = file.read(base + r.collection, 16);
  if (!head || std::memcmp(head->data(), "GCOL", 4) != 0 || (*head)[4] != 1)
    throw Damage{"its global heap collection is missing or damaged"};
  const std::uint64_t size = little(&(*head)[8], 8);
  const auto heap = size >= 16 ? file.read(base + r.collection, size) : std::nullopt;
  if (!heap) throw Damage{"its global heap collection runs past the end of the file"};
  std::optional<std::uint64_t> objectSize;
  std::uint64_t p = 16;
  while (p < size) {
    if (p + 16 > size) break;  // too small for an object: free space
    const std::uint8_t* h = heap->data() + p;
    const std::uint64_t index = little(h, 2), length = little(h + 8, 8);
    std::uint64_t need = length;  // object 0 is the free space, its size all of it
    if (index > 0) {
      if (length > size) throw Damage{"an object of its global heap collection overruns it"};
      need = 16 + ((length + 7) & ~std::uint64_t{7});
      if (index == r.index) objectSize = length;
    }
    if (need == 0 || need > size - p)
      throw Damage{"an object of its global heap collection overruns it"};
    p += need;
  }
  if (!objectSize) throw Damage{"its text's global heap object is missing"};
  if (*objectSize != r.length) throw Damage{"its length and its text's global heap object's differ"};
}

}  // namespace

void checkHeapString(hid_t object, const std::string& name) {
  H5O_info_t info;
  if (H5Oget_info2(object, &info, H5O_INFO_BASIC) < 0) return;  // HDF5 says why, reading
  const ssize_t nameLength = H5Fget_name(object, nullptr, 0);
  if (nameLength <= 0) return;
  std::string path(static_cast<std::size_t>(nameLength) + 1, '\0');
  H5Fget_name(object, path.data(), path.size());
  path.resize(static_cast<std::size_t>(nameLength));
  Handle file = checked(H5Iget_file_id(object), "find the object's file");
  Handle fcpl = checked(H5Fget_create_plist(file.get()), "read the file creation properties");
  hsize_t base = 0;
  check(H5Pget_userblock(fcpl.get(), &base), "read the user block size");
  const RawFile raw(path);
  if (!raw.open()) return;
  try {
    const std::optional<HeapReference> r = findReference(raw, base, info.addr, name);
    if (r && r->collection != 0) checkCollection(raw, base, *r);
  } catch (const Damage& d) {
    throw Error(d.what, "");
  }
}

}  // namespace sph::io::h5
