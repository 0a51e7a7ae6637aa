// Checks of what a damaged file could make HDF5 1.10 do before it does it (Hdf5.h: checkHeapString,
// openCheckedDataset). HDF5 trusts the sizes it reads: it copies a global heap object by the size
// the heap records into a buffer sized by the length the attribute records, walks a heap
// collection by its objects' sizes without bounds, and allocates a dataset's chunk by the
// dimensions its layout records. Global heap collections carry no checksum (the object headers
// around them do); a layout's fields pass their header's checksum when only they were changed
// with it. The heap check reads the file here, by the HDF5 file format specification (version 2
// object headers, version 3 attribute messages: what this project writes); a layout it does not
// know is left to HDF5.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/cache/Hdf5.h"

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

std::uint64_t little(const std::uint8_t* p, int bytes) {
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
  HeaderMessages(const RawFile& file, std::uint64_t base, std::uint64_t address) {
    const auto start = file.read(base + address, 16);
    if (!start || std::memcmp(start->data(), "OHDR", 4) != 0 || (*start)[4] != 2) return;
    const unsigned flags = (*start)[5];
    std::size_t at = 6;
    if (flags & 0x20) at += 16;  // access, modification, change and birth times
    if (flags & 0x10) at += 4;   // attribute phase change values
    const std::size_t sizeBytes = std::size_t{1} << (flags & 0x03);
    const auto prefix = file.read(base + address, at + sizeBytes);
    if (!prefix) throw Damage{"its object header runs past the end of the file"};
    const std::uint64_t chunkSize = little(&(*prefix)[at], static_cast<int>(sizeBytes));
    auto first = file.read(base + address, at + sizeBytes + chunkSize);
    if (!first) throw Damage{"its object header runs past the end of the file"};
    const std::size_t prefixBytes = (flags & 0x04) ? 6 : 4;  // with creation order, or not
    chunks_.push_back(std::move(*first));
    scan(chunks_.back(), at + sizeBytes, chunks_.back().size(), prefixBytes);
    for (std::size_t i = 0; i < more_.size(); ++i) {
      if (i == 1024) throw Damage{"its object header has over 1024 continuation chunks"};
      auto next = file.read(base + more_[i].first, more_[i].second);
      if (!next || next->size() < 8 || std::memcmp(next->data(), "OCHK", 4) != 0)
        throw Damage{"a continuation of its object header lies outside the file"};
      chunks_.push_back(std::move(*next));
      scan(chunks_.back(), 4, chunks_.back().size() - 4, prefixBytes);
    }
  }
  const std::vector<Message>& messages() const { return messages_; }

 private:
  void scan(const std::vector<std::uint8_t>& chunk, std::size_t p, std::size_t end,
            std::size_t prefixBytes) {
    while (p + prefixBytes <= end) {
      Message m;
      m.type = chunk[p];
      m.size = little(&chunk[p + 1], 2);
      m.flags = chunk[p + 3];
      const std::size_t body = p + prefixBytes;
      if (body + m.size > end) throw Damage{"a message of its object header runs past its chunk"};
      m.body = &chunk[body];
      if (m.type == 0x10 && m.size >= 16)  // continuation: offset and length of the next chunk
        more_.emplace_back(little(m.body, 8), little(m.body + 8, 8));
      messages_.push_back(m);
      p = body + m.size;
    }
  }

  std::vector<std::vector<std::uint8_t>> chunks_;  // (a deque's worth: never reallocated into)
  std::vector<std::pair<std::uint64_t, std::uint64_t>> more_;
  std::vector<Message> messages_;
};

// Where a variable-length string attribute's value points: its length and heap object.
struct HeapReference {
  std::uint64_t length = 0, collection = 0;
  std::uint32_t index = 0;
};

// The attribute `name` of the header's messages, if it is a variable-length string this project
// writes (a version 2 or 3 attribute message without shared parts).
std::optional<HeapReference> findReference(const HeaderMessages& header, const std::string& name) {
  for (const Message& m : header.messages()) {
    if (m.type != 0x0C || m.size < 8) continue;
    const unsigned version = m.body[0], flags = m.body[1];
    const std::size_t nameSize = little(m.body + 2, 2), typeSize = little(m.body + 4, 2);
    const std::size_t spaceSize = little(m.body + 6, 2);
    const std::size_t nameAt = version == 3 ? 9 : 8;
    if (nameSize == 0 || nameAt + nameSize > m.size ||
        std::string(reinterpret_cast<const char*>(m.body + nameAt), nameSize - 1) != name)
      continue;
    if (version < 2 || flags != 0) return std::nullopt;  // a layout this project does not write
    const std::size_t typeAt = nameAt + nameSize, data = typeAt + typeSize + spaceSize;
    if (typeSize < 2 || data + 16 > m.size) throw Damage{"its attribute message is cut short"};
    // Not a variable-length string: nothing of the heap's is read.
    if ((m.body[typeAt] & 0x0F) != 9 || (m.body[typeAt + 1] & 0x0F) != 1) return std::nullopt;
    HeapReference r;
    r.length = little(m.body + data, 4);
    r.collection = little(m.body + data + 4, 8);
    r.index = static_cast<std::uint32_t>(little(m.body + data + 12, 4));
    return r;
  }
  return std::nullopt;
}

// A dataspace message's element count (a scalar has one, a null space none), its dimensions in
// `dims`; `bytes` of it are the message.
std::uint64_t spaceElements(const std::uint8_t* p, std::size_t bytes, std::vector<std::uint64_t>& dims) {
  if (bytes < 4) throw Damage{"a dataspace message is cut short"};
  const unsigned version = p[0], rank = p[1], flags = p[2];
  if ((version != 1 && version != 2) || rank > 32) throw Damage{"a dataspace message is not one"};
  const std::size_t at = version == 1 ? 8 : 4;
  if (at + std::size_t{8} * rank * ((flags & 1) ? 2 : 1) > bytes)
    throw Damage{"a dataspace message is cut short"};
  if (version == 2 && p[3] == 2) return 0;  // null
  long double n = 1;
  dims.clear();
  for (unsigned d = 0; d < rank; ++d) {
    dims.push_back(little(p + at + 8 * d, 8));
    n *= static_cast<long double>(dims.back());
  }
  if (n > 1e18L) throw Damage{"a dataspace of over 10^18 elements"};
  return static_cast<std::uint64_t>(n);
}

// A datatype message's element size in the file (a variable-length one's: its heap reference).
std::uint64_t typeBytes(const std::uint8_t* p, std::size_t bytes) {
  if (bytes < 8) throw Damage{"a datatype message is cut short"};
  const std::uint64_t size = little(p + 4, 4);
  if (size == 0) throw Damage{"a datatype of size 0"};
  return (p[0] & 0x0F) == 9 ? 16 : size;
}

// Every message of a header that HDF5 would follow or size something by, checked against the
// file before HDF5 decodes it: addresses undefined or at a block of the kind they name (HDF5
// reads a block's header before checking its signature, and past its buffers at an address that
// holds something else), links and attributes whole within their message, and a dataset's
// shape, element size and layout consistent with each other and with the file's size (HDF5
// allocates a chunk by the dimensions the layout records, before any data is read).
void checkMessages(const RawFile& file, std::uint64_t base, const HeaderMessages& header) {
  constexpr std::uint64_t kUndefined = ~std::uint64_t{0};
  const std::uint64_t fileSize = file.size() - base;
  auto points = [&](const std::uint8_t* p, const char* signature, const char* what) {
    const std::uint64_t address = little(p, 8);
    if (address == kUndefined) return;
    const auto head = address < fileSize ? file.read(base + address, 4) : std::nullopt;
    if (!head || std::memcmp(head->data(), signature, 4) != 0)
      throw Damage{std::string("its ") + what + " points to no " + signature + " block"};
  };
  std::vector<std::uint64_t> spaceDims;
  std::uint64_t elements = 0, elementBytes = 0;
  bool haveSpace = false, haveType = false;
  const Message* layout = nullptr;
  for (const Message& m : header.messages()) {
    const std::uint8_t* p = m.body;
    // A shared message stands for one in the file's shared message table, which this project's
    // files do not have (HDF5 reads that table from wherever the damaged message says).
    if (m.flags & 0x02) throw Damage{"a shared message, in a file without shared messages"};
    // A message of a kind HDF5 does not know it skips: a dataset whose filter pipeline message
    // became one is read as if unfiltered, its compressed chunk copied as a whole one. And an
    // external file list (0x07) would read another file; no cache has one.
    if (m.type > 0x17 || m.type == 0x07 || m.type == 0x09)
      throw Damage{"a message of a kind no cache holds"};
    switch (m.type) {
      case 0x01:  // dataspace
        elements = spaceElements(p, m.size, spaceDims), haveSpace = true;
        break;
      case 0x03:  // datatype
        elementBytes = typeBytes(p, m.size), haveType = true;
        break;
      case 0x08:  // layout
        layout = &m;
        break;
      case 0x02:    // link info
      case 0x15: {  // attribute info
        const unsigned flags = m.size >= 2 ? p[1] : 0;
        const std::size_t at = 2 + ((flags & 0x01) ? (m.type == 0x02 ? 8 : 2) : 0);
        const int addresses = (flags & 0x02) ? 3 : 2;
        if (at + std::size_t{8} * addresses > m.size)
          throw Damage{"its link or attribute info is cut short"};
        const char* what = m.type == 0x02 ? "dense link storage" : "dense attribute storage";
        points(p + at, "FRHP", what);
        for (int i = 1; i < addresses; ++i) points(p + at + 8 * i, "BTHD", what);
        break;
      }
      case 0x06: {  // link
        if (m.size < 3 || p[0] != 1) throw Damage{"a link message is not one"};
        const unsigned flags = p[1];
        std::size_t at = 2;
        unsigned type = 0;
        if (flags & 0x08) type = p[at++];
        if (flags & 0x04) at += 8;  // creation order
        if (flags & 0x10) at += 1;  // character set
        const std::size_t lengthBytes = std::size_t{1} << (flags & 0x03);
        if (at + lengthBytes > m.size) throw Damage{"a link message is cut short"};
        const std::uint64_t nameLength = little(p + at, static_cast<int>(lengthBytes));
        at += lengthBytes;
        if (nameLength == 0 || nameLength > m.size - at) throw Damage{"a link's name overruns it"};
        at += nameLength;
        if (type == 0) {
          if (at + 8 > m.size) throw Damage{"a link message is cut short"};
          points(p + at, "OHDR", "link");
        } else if (type == 1 || type == 64) {
          if (at + 2 > m.size || little(p + at, 2) > m.size - at - 2)
            throw Damage{"a link's target overruns it"};
        } else {
          throw Damage{"a link of an unknown kind"};
        }
        break;
      }
      case 0x0C: {  // attribute (version 2 and 3: this project's; others are HDF5's to read)
        if (m.size < 8 || p[0] < 1 || p[0] > 3) throw Damage{"an attribute message is not one"};
        if (p[0] == 1) break;  // HDF5 1.6's padded layout: HDF5's to read
        const std::size_t nameSize = little(p + 2, 2), typeSize = little(p + 4, 2);
        const std::size_t spaceSize = little(p + 6, 2), nameAt = p[0] == 3 ? 9 : 8;
        const std::size_t dataAt = nameAt + nameSize + typeSize + spaceSize;
        if (nameSize == 0 || dataAt > m.size || p[nameAt + nameSize - 1] != 0)
          throw Damage{"an attribute message overruns it"};
        if (p[1] != 0) break;  // shared datatype or dataspace
        std::vector<std::uint64_t> dims;
        const long double data =
            static_cast<long double>(typeBytes(p + nameAt + nameSize, typeSize)) *
            static_cast<long double>(spaceElements(p + nameAt + nameSize + typeSize, spaceSize, dims));
        if (data > static_cast<long double>(m.size - dataAt))
          throw Damage{"an attribute's value overruns its message"};
        break;
      }
      case 0x0B: {  // filter pipeline: each filter whole within the message
        if (m.size < 2 || (p[0] != 1 && p[0] != 2) || p[1] > 32)
          throw Damage{"a filter pipeline message is not one"};
        std::size_t at = p[0] == 1 ? 8 : 2;
        for (unsigned f = 0; f < p[1]; ++f) {
          if (at + 2 > m.size) throw Damage{"a filter pipeline message is cut short"};
          const std::uint64_t id = little(p + at, 2);
          const bool named = p[0] == 1 || id >= 256;
          const std::size_t fixed = named ? 8 : 6;
          if (at + fixed > m.size) throw Damage{"a filter pipeline message is cut short"};
          std::uint64_t nameLength = named ? little(p + at + 2, 2) : 0;
          const std::uint64_t values = little(p + at + fixed - 2, 2);
          if (p[0] == 1) nameLength = (nameLength + 7) & ~std::uint64_t{7};
          at += fixed + nameLength + 4 * values + (p[0] == 1 && values % 2 ? 4 : 0);
          if (at > m.size) throw Damage{"a filter of its pipeline overruns the message"};
        }
        break;
      }
      case 0x11:  // symbol table: version 1 B-tree and local heap
        if (m.size < 16) throw Damage{"its symbol table message is cut short"};
        points(p, "TREE", "symbol table"), points(p + 8, "HEAP", "symbol table");
        break;
      default:
        break;
    }
  }
  if (!layout) return;
  if (!haveSpace || !haveType) throw Damage{"a dataset without its shape or type"};
  // Deflate packs at most 1032 bytes into one (zlib's limit): no dataset of a file holds more.
  const long double bytes = static_cast<long double>(elements) * elementBytes;
  if (bytes > 1032.0L * fileSize + 65536) throw Damage{"a dataset larger than the file can hold"};
  const std::uint8_t* p = layout->body;
  const std::size_t n = layout->size;
  // Versions 3 and 4 are what HDF5 1.8 and later write (HDF5's older ones, which it would decode
  // differently, are no cache's).
  if (n < 2 || (p[0] != 3 && p[0] != 4)) throw Damage{"a layout message of an unknown version"};
  if (p[1] == 0) {  // compact
    if (n < 4 || little(p + 2, 2) > n - 4 || little(p + 2, 2) != bytes)
      throw Damage{"a compact dataset's data is not its shape's"};
  } else if (p[1] == 1) {  // contiguous
    if (n < 18) throw Damage{"a layout message is cut short"};
    const std::uint64_t address = little(p + 2, 8), size = little(p + 10, 8);
    if (address != kUndefined && (address > fileSize || size > fileSize - address))
      throw Damage{"a contiguous dataset lies past the end of the file"};
    if (size != bytes) throw Damage{"a contiguous dataset's data is not its shape's"};
  } else if (p[1] == 2) {  // chunked
    std::vector<std::uint64_t> chunk;
    if (p[0] == 3) {
      const unsigned rank = n >= 3 ? p[2] : 0;
      if (rank < 1 || 11 + std::size_t{4} * rank > n) throw Damage{"a layout message is cut short"};
      for (unsigned d = 0; d < rank; ++d) chunk.push_back(little(p + 11 + 4 * d, 4));
    } else {
      const unsigned rank = n >= 4 ? p[3] : 0, width = n >= 5 ? p[4] : 0;
      if (rank < 1 || width < 1 || width > 8 || 5 + std::size_t{width} * rank > n)
        throw Damage{"a layout message is cut short"};
      for (unsigned d = 0; d < rank; ++d)
        chunk.push_back(little(p + 5 + width * d, static_cast<int>(width)));
    }
    // The last "dimension" is the element's size.
    if (chunk.size() != spaceDims.size() + 1) throw Damage{"a chunk of another shape"};
    for (std::size_t d = 0; d < spaceDims.size(); ++d) {
      if (chunk[d] == 0 || chunk[d] > std::max<std::uint64_t>(spaceDims[d], 1))
        throw Damage{"a chunk larger than its dataset"};
    }
    if (chunk.back() != elementBytes && !(elementBytes == 16 && chunk.back() == 16))
      throw Damage{"a chunk of another element size"};
  } else if (p[1] != 3) {  // 3: virtual
    throw Damage{"a layout of an unknown class"};
  }
}

// The file an object is in, opened for the checks, and where HDF5's addresses start in it (past
// the user block). The last one stays open while the same file (by path, device and inode) is
// checked again: a reader checks a header or two per frame, thousands per cache, and opening the
// file and asking HDF5 for its properties each time cost more than the check.
struct FileOf {
  std::shared_ptr<RawFile> raw;
  std::uint64_t base = 0;
};

FileOf fileOf(hid_t object) {
  struct Kept {
    std::string path;
    dev_t device = 0;
    ino_t inode = 0;
    FileOf file;
  };
  thread_local Kept kept;
  const ssize_t nameLength = H5Fget_name(object, nullptr, 0);
  if (nameLength <= 0) return {};
  std::string path(static_cast<std::size_t>(nameLength) + 1, '\0');
  H5Fget_name(object, path.data(), path.size());
  path.resize(static_cast<std::size_t>(nameLength));
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return {};
  if (kept.file.raw && kept.path == path && kept.device == st.st_dev && kept.inode == st.st_ino) {
    kept.file.raw->refresh();
    return kept.file;
  }
  Handle file = checked(H5Iget_file_id(object), "find the object's file");
  Handle fcpl = checked(H5Fget_create_plist(file.get()), "read the file creation properties");
  hsize_t base = 0;
  check(H5Pget_userblock(fcpl.get(), &base), "read the user block size");
  kept.path = path, kept.device = st.st_dev, kept.inode = st.st_ino;
  kept.file.raw = std::make_shared<RawFile>(path);
  kept.file.base = base;
  if (!kept.file.raw->open()) kept.file.raw.reset();
  return kept.file;
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

void checkObjectHeader(hid_t inFile, std::uint64_t address, const std::string& name) {
  const FileOf f = fileOf(inFile);
  if (!f.raw) return;
  const RawFile& raw = *f.raw;
  try {
    checkMessages(raw, f.base, HeaderMessages(raw, f.base, address));
  } catch (const Damage& d) {
    throw Error("'" + name + "' is damaged", d.what);
  }
}

}  // namespace

void checkHeapString(hid_t object, const std::string& name) {
  H5O_info_t info;
  if (H5Oget_info2(object, &info, H5O_INFO_BASIC) < 0) return;  // HDF5 says why, reading
  const FileOf f = fileOf(object);
  if (!f.raw) return;
  const RawFile& raw = *f.raw;
  try {
    const std::optional<HeapReference> r =
        findReference(HeaderMessages(raw, f.base, info.addr), name);
    if (r && r->collection != 0) checkCollection(raw, f.base, *r);
  } catch (const Damage& d) {
    throw Error(d.what, "");
  }
}

void checkRootHeader(const std::string& path) {
  const RawFile raw(path);
  if (!raw.open()) return;
  // The superblock (version 2 or 3) at 0 or a power of two from 512 on, past the user block: its
  // base address, then the root group's object header address.
  for (std::uint64_t at = 0; at + 48 <= raw.size(); at = at == 0 ? 512 : 2 * at) {
    const auto block = raw.read(at, 48);
    if (!block || std::memcmp(block->data(), "\x89HDF\r\n\x1a\n", 8) != 0) continue;
    if ((*block)[8] < 2 || (*block)[9] != 8 || (*block)[10] != 8) return;  // HDF5 reads others
    // A file shorter than its superblock says (the end of file as a file offset, the user block
    // included): HDF5 refuses it as truncated, the better words.
    if (raw.size() < little(&(*block)[28], 8)) return;
    try {
      checkMessages(raw, at, HeaderMessages(raw, at, little(&(*block)[36], 8)));
    } catch (const Damage& d) {
      throw Error("its root group is damaged", d.what);
    }
    return;
  }
}

void checkHeaders(hid_t loc, const std::string& name) {
  // Component by component: each group's header is checked before HDF5 looks up a link in it.
  hid_t at = loc;
  Handle held;
  std::size_t from = name.empty() || name[0] != '/' ? 0 : 1;
  while (from < name.size()) {
    const std::size_t slash = std::min(name.find('/', from), name.size());
    const std::string part = name.substr(from, slash - from);
    H5L_info_t link;
    check(H5Lget_info(at, part.c_str(), &link, H5P_DEFAULT), "find '" + name + "'");
    if (link.type == H5L_TYPE_HARD) checkObjectHeader(at, link.u.address, name);
    if (slash < name.size()) {
      held = checked(H5Oopen(at, part.c_str(), H5P_DEFAULT), "open '" + name + "'");
      at = held.get();
    }
    from = slash + 1;
  }
}

Handle openCheckedGroup(hid_t loc, const std::string& name) {
  checkHeaders(loc, name);
  return checked(H5Gopen2(loc, name.c_str(), H5P_DEFAULT), "open the group '" + name + "'");
}

Handle openCheckedDataset(hid_t loc, const std::string& name) {
  checkHeaders(loc, name);
  Handle set = checked(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), "open dataset '" + name + "'");
  auto damaged = [&](const std::string& what) {
    return Error("dataset '" + name + "' is damaged", what);
  };
  Handle type = checked(H5Dget_type(set.get()), "read the type of dataset '" + name + "'");
  Handle space = checked(H5Dget_space(set.get()), "read the shape of dataset '" + name + "'");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > 8) throw damaged("a shape of " + std::to_string(rank) + " dimensions");
  hsize_t dims[8] = {0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  // Its bytes once read, overflow checked: what the caller allocates.
  long double bytes = static_cast<long double>(H5Tget_size(type.get()));
  for (int d = 0; d < rank; ++d) bytes *= static_cast<long double>(dims[d]);
  if (bytes == 0) return set;
  Handle file = checked(H5Iget_file_id(set.get()), "find the dataset's file");
  hsize_t fileSize = 0;
  check(H5Fget_filesize(file.get(), &fileSize), "read the file's size");
  Handle dcpl = checked(H5Dget_create_plist(set.get()), "read the layout of '" + name + "'");
  const H5D_layout_t layout = H5Pget_layout(dcpl.get());
  // Deflate packs at most 1032 bytes into one (zlib's limit): no chunk of a file holds more.
  constexpr long double kMostInflation = 1032;
  if (layout == H5D_CONTIGUOUS) {
    const haddr_t at = H5Dget_offset(set.get());
    if (at == HADDR_UNDEF || static_cast<long double>(at) + bytes > fileSize)
      throw damaged("its " + std::to_string(static_cast<unsigned long long>(bytes)) +
                    " bytes are not in the file");
  } else if (layout == H5D_CHUNKED) {
    hsize_t chunk[8] = {0};
    if (H5Pget_chunk(dcpl.get(), rank, chunk) != rank) throw damaged("its chunk has another shape");
    long double chunkBytes = static_cast<long double>(H5Tget_size(type.get()));
    for (int d = 0; d < rank; ++d) {
      if (chunk[d] == 0 || chunk[d] > dims[d]) throw damaged("a chunk larger than the dataset");
      chunkBytes *= static_cast<long double>(chunk[d]);
    }
    // The filters this project's caches use; without deflate a chunk is stored at its size.
    bool inflates = false;
    std::uint64_t checksumBytes = 0;
    const int filters = H5Pget_nfilters(dcpl.get());
    for (int f = 0; f < filters; ++f) {
      unsigned flags = 0, config = 0;
      std::size_t values = 0;
      const H5Z_filter_t id = H5Pget_filter2(dcpl.get(), static_cast<unsigned>(f), &flags,
                                             &values, nullptr, 0, nullptr, &config);
      if (id == H5Z_FILTER_DEFLATE)
        inflates = true;
      else if (id == H5Z_FILTER_FLETCHER32)
        checksumBytes = 4;
      else if (id != H5Z_FILTER_SHUFFLE)
        throw damaged("a filter no cache uses (" + std::to_string(id) + ")");
    }
    hsize_t chunks = 0;
    check(H5Dget_num_chunks(set.get(), space.get(), &chunks), "count the chunks of '" + name + "'");
    long double stored = 0;
    for (hsize_t i = 0; i < chunks; ++i) {
      hsize_t offset[8] = {0}, size = 0;
      haddr_t at = HADDR_UNDEF;
      unsigned mask = 0;
      check(H5Dget_chunk_info(set.get(), space.get(), i, offset, &mask, &at, &size),
            "read chunk " + std::to_string(i) + " of '" + name + "'");
      if (at == HADDR_UNDEF || at > fileSize || size > fileSize - at ||
          chunkBytes > kMostInflation * static_cast<long double>(size) + 64)
        throw damaged("chunk " + std::to_string(i) + " is not in the file");
      // Every filter applied (a skipped one leaves data HDF5 would read as filtered), and an
      // uncompressed chunk exactly its size (HDF5 copies the chunk's size out of what it read).
      if (mask != 0 || (!inflates && static_cast<long double>(size) != chunkBytes + checksumBytes))
        throw damaged("chunk " + std::to_string(i) + " is not stored as its filters say");
      stored += static_cast<long double>(size);
    }
    if (bytes > kMostInflation * stored + 64)
      throw damaged("its " + std::to_string(static_cast<unsigned long long>(bytes)) +
                    " bytes cannot come from the " +
                    std::to_string(static_cast<unsigned long long>(stored)) + " it stores");
  } else if (layout != H5D_COMPACT) {
    throw damaged("a layout the cache does not use");
  }
  return set;
}

}  // namespace sph::io::h5
