// The checks of object headers before HDF5 decodes them (Hdf5.h: checkHeaders, openCheckedGroup,
// checkRootHeader). HDF5 1.10 trusts the sizes and addresses it reads: it reads a block's header
// at whatever address a message names before checking its signature, and sizes what it allocates
// by the shapes and layouts the messages record. A header's checksum does not stop that when
// only a message's fields were changed with it. Each header on the way to an object is read
// here from the file (Hdf5FileBytes.h; version 2 object headers, what this project writes) and
// every message HDF5 would follow or size something by is checked against the file; a header of
// another version is left to HDF5.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/cache/Hdf5FileBytes.h"

namespace sph::io::cache::h5 {
namespace {

using detail::Damage;
using detail::FileOf;
using detail::fileOf;
using detail::HeaderMessages;
using detail::little;
using detail::Message;
using detail::RawFile;

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

}  // namespace sph::io::cache::h5
