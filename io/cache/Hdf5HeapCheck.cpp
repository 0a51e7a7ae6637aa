// The check of a variable-length string attribute before HDF5 reads it (Hdf5.h:
// checkHeapString). Its characters lie in a global heap collection, which carries no checksum
// (the object headers around it do), and HDF5 1.10 copies the heap object by the size the heap
// records into a buffer sized by the length the attribute records, and walks the collection by
// its objects' sizes without bounds. The attribute is found in its object header (version 3
// attribute messages: what this project writes) and its collection walked here, from the file.
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

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

}  // namespace sph::io::cache::h5
