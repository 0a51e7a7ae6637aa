// An object header's messages and the file an object is in, read from the file's bytes
// (Hdf5FileBytes.h).
#include "io/cache/Hdf5FileBytes.h"

#include <cstring>

namespace sph::io::cache::h5::detail {

HeaderMessages::HeaderMessages(const RawFile& file, std::uint64_t base, std::uint64_t address) {
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

void HeaderMessages::scan(const std::vector<std::uint8_t>& chunk, std::size_t p, std::size_t end,
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

}  // namespace sph::io::cache::h5::detail
