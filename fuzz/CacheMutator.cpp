#include "fuzz/CacheMutator.h"

#include <algorithm>
#include <functional>
#include <cstring>
#include <sstream>

#include "fuzz/Lookup3.h"

namespace sph::fuzz {
namespace {

std::uint64_t little(const std::uint8_t* p, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = bytes; i-- > 0;) v = (v << 8) | p[i];
  return v;
}

void putLittle(std::uint8_t* p, std::size_t bytes, std::uint64_t v) {
  for (std::size_t i = 0; i < bytes; ++i, v >>= 8) p[i] = static_cast<std::uint8_t>(v);
}

bool hasChecksum(const Bytes& b, std::size_t at, std::size_t length) {
  return length >= 8 && at + length <= b.size() &&
         lookup3(&b[at], length - 4) == little(&b[at + length - 4], 4);
}

std::string hex(std::uint64_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v;
  return s.str();
}

// Values that make sizes and counts interesting: empty, one, the edges of each width, huge, and
// the old value nudged.
std::uint64_t interestingValue(std::uint64_t old, std::size_t width, std::mt19937_64& random) {
  const std::uint64_t all = width >= 8 ? ~std::uint64_t{0} : (std::uint64_t{1} << (8 * width)) - 1;
  const std::uint64_t choices[] = {0,          1,          2,           0x7f,     0x80,
                                   0xff,       0xffff,     0x7fffffff,  0xffffffff, std::uint64_t{1} << 40,
                                   all,        old + 1,    old - 1,     old * 2,  old / 2,
                                   old + 4096, random()};
  return choices[random() % (sizeof choices / sizeof choices[0])] & all;
}

const char* const kOtherSignatures[] = {"BTHD", "BTIN", "BTLF", "FRHP", "FHIB", "FHDB", "FAHD",
                                        "FADB", "EAHD", "EAIB", "EASB", "EADB", "SMTB", "SMLI"};

}  // namespace

CacheMutator::CacheMutator(Bytes file) : file_(std::move(file)) {
  // HDF5's data starts at the superblock, past the user block (which holds the journal: a copy
  // of the root group's header that only a repair reads, not to be taken for the header).
  for (std::size_t at = 0; at + 8 <= file_.size(); at = at == 0 ? 512 : at * 2) {
    if (std::memcmp(&file_[at], "\x89HDF\r\n\x1a\n", 8) == 0) {
      base_ = at;
      break;
    }
  }
  findObjectHeaders();
  findOtherBlocks();
  findHeapCollections();
}

void CacheMutator::findObjectHeaders() {
  const Bytes& b = file_;
  std::vector<std::pair<std::size_t, std::size_t>> continuations;  // file offsets found
  // Addresses in messages are relative to the superblock (after the user block).
  const std::size_t base = base_;
  auto scan = [&](Block& block, std::size_t begin, std::size_t end, bool creationOrder) {
    const std::size_t prefix = creationOrder ? 6 : 4;
    for (std::size_t p = begin; p + prefix <= end;) {
      Message m;
      m.at = p;
      m.prefix = prefix;
      m.type = b[p];
      m.size = prefix + little(&b[p + 1], 2);
      if (p + m.size > end) break;
      if (m.type == 0x10 && m.size >= prefix + 16)
        continuations.emplace_back(base + little(&b[p + prefix], 8),
                                   little(&b[p + prefix + 8], 8));
      block.messages.push_back(m);
      p += m.size;
    }
  };
  for (std::size_t at = base_; at + 16 <= b.size(); ++at) {
    if (std::memcmp(&b[at], "OHDR", 4) != 0 || b[at + 4] != 2) continue;
    const unsigned flags = b[at + 5];
    std::size_t prefix = 6 + ((flags & 0x20) ? 16 : 0) + ((flags & 0x10) ? 4 : 0);
    const std::size_t sizeBytes = std::size_t{1} << (flags & 0x03);
    if (at + prefix + sizeBytes > b.size()) continue;
    const std::uint64_t chunk = little(&b[at + prefix], sizeBytes);
    prefix += sizeBytes;
    if (chunk > b.size() || !hasChecksum(b, at, prefix + chunk + 4)) continue;
    Block block;
    block.at = at, block.length = prefix + chunk + 4, block.kind = "OHDR";
    scan(block, at + prefix, at + prefix + chunk, (flags & 0x04) != 0);
    blocks_.push_back(std::move(block));
  }
  for (std::size_t i = 0; i < continuations.size() && i < 4096; ++i) {
    const auto [at, length] = continuations[i];
    if (at + 8 > b.size() || std::memcmp(&b[at], "OCHK", 4) != 0 || !hasChecksum(b, at, length))
      continue;
    Block block;
    block.at = at, block.length = length, block.kind = "OCHK";
    scan(block, at + 4, at + length - 4, false);
    blocks_.push_back(std::move(block));
  }
}

void CacheMutator::findOtherBlocks() {
  const Bytes& b = file_;
  for (std::size_t at = base_; at + 12 <= b.size(); ++at) {
    for (const char* signature : kOtherSignatures) {
      if (std::memcmp(&b[at], signature, 4) != 0) continue;
      // The block's length is where its checksum matches (these blocks are small, but for the
      // data blocks of arrays of many chunks).
      for (std::size_t length = 12; length <= 16384 && at + length <= b.size(); ++length) {
        if (!hasChecksum(b, at, length)) continue;
        Block block;
        block.at = at, block.length = length, block.kind = signature;
        blocks_.push_back(std::move(block));
        break;
      }
    }
  }
}

void CacheMutator::findHeapCollections() {
  const Bytes& b = file_;
  for (std::size_t at = base_; at + 16 <= b.size(); ++at) {
    if (std::memcmp(&b[at], "GCOL", 4) != 0 || b[at + 4] != 1) continue;
    const std::uint64_t size = little(&b[at + 8], 8);
    if (size < 16 || size > b.size() - at) continue;
    Block block;
    block.at = at, block.length = size, block.kind = "GCOL", block.checksummed = false;
    // Its objects as messages: each object's 16-byte header (index, references, size).
    for (std::size_t p = at + 16; p + 16 <= at + size;) {
      Message m;
      m.at = p;
      m.type = static_cast<unsigned>(little(&b[p], 2));
      const std::uint64_t length = little(&b[p + 8], 8);
      m.prefix = 16;
      m.size = 16 + ((length + 7) & ~std::uint64_t{7});
      if (m.type == 0 || m.size > at + size - p) break;  // the free space ends the objects
      block.messages.push_back(m);
      p += m.size;
    }
    blocks_.push_back(std::move(block));
  }
}

Bytes CacheMutator::mutate(std::mt19937_64& random, std::string& what) const {
  Bytes bytes = file_;
  const int mutations = random() % 8 == 0 ? 2 : 1;
  for (int k = 0; k < mutations && !bytes.empty(); ++k) {
    if (k > 0) what += "; ";
    const unsigned kind = random() % 10;
    if (kind < 5 && !blocks_.empty()) {
      mutateMetadata(bytes, random, what);
    } else if (kind < 7) {
      const std::size_t n = 1 + random() % 4;
      const std::size_t at = random() % bytes.size();
      for (std::size_t i = 0; i < n && at + i < bytes.size(); ++i)
        bytes[at + i] = static_cast<std::uint8_t>(random());
      what += "flip " + std::to_string(n) + " bytes at " + std::to_string(at);
    } else if (kind < 9) {
      const std::size_t at = random() % bytes.size();
      const std::size_t n = std::min<std::size_t>(1 + random() % 4096, bytes.size() - at);
      std::fill(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                bytes.begin() + static_cast<std::ptrdiff_t>(at + n), 0);
      what += "zero " + std::to_string(n) + " bytes at " + std::to_string(at);
    } else {
      const std::size_t size = random() % bytes.size();
      bytes.resize(size);
      what += "truncate to " + std::to_string(size) + " bytes";
    }
  }
  return bytes;
}

void CacheMutator::mutateMetadata(Bytes& bytes, std::mt19937_64& random, std::string& what) const {
  const Block& block = blocks_[random() % blocks_.size()];
  // A field inside one of its messages (or objects), or anywhere in the block.
  std::size_t begin = block.at + 4;  // past the signature
  std::size_t end = block.at + block.length - (block.checksummed ? 4 : 0);
  std::string where = block.kind + " at " + std::to_string(block.at);
  if (!block.messages.empty() && random() % 4 != 0) {
    const Message& m = block.messages[random() % block.messages.size()];
    begin = m.at, end = std::min(end, m.at + m.size);
    where += ", message " + hex(m.type) + " at " + std::to_string(m.at);
  }
  if (end <= begin || end > bytes.size()) return;
  const std::size_t at = begin + random() % (end - begin);
  const std::size_t widths[] = {1, 2, 4, 8};
  const std::size_t width = std::min(widths[random() % 4], end - at);
  const std::uint64_t old = little(&bytes[at], width);
  const std::uint64_t value = interestingValue(old, width, random);
  putLittle(&bytes[at], width, value);
  const std::size_t sumAt = block.at + block.length - 4;
  if (block.checksummed && sumAt + 4 <= bytes.size())
    putLittle(&bytes[sumAt], 4, lookup3(&bytes[block.at], block.length - 4));
  what += where + ": " + std::to_string(width) + " bytes at " + std::to_string(at) + " = " +
          hex(value) + (block.checksummed ? ", checksum kept" : "");
}

std::vector<std::pair<std::string, Bytes>> CacheMutator::corpus() const {
  std::vector<std::pair<std::string, Bytes>> out;
  // `change` writes `width` bytes of `value` at `offset` of the body of the first message of
  // `type` (in a block whose messages also hold `alongside`, if given) whose body has `needs`
  // bytes and `where` accepts, and keeps the block's checksum.
  auto add = [&](const std::string& name, unsigned type, std::size_t offset, std::size_t width,
                 std::uint64_t value, std::size_t needs = 0, unsigned alongside = 0,
                 const std::function<bool(const std::uint8_t*)>& where = nullptr) {
    for (const Block& block : blocks_) {
      if (block.kind != "OHDR" && block.kind != "OCHK") continue;
      bool has = alongside == 0;
      for (const Message& m : block.messages) has = has || m.type == alongside;
      if (!has) continue;
      for (const Message& m : block.messages) {
        const std::size_t body = m.at + m.prefix, bodySize = m.size - m.prefix;
        if (m.type != type || bodySize < std::max(needs, offset + width)) continue;
        if (where && !where(&file_[body])) continue;
        Bytes bytes = file_;
        putLittle(&bytes[body + offset], width, value);
        const std::size_t sumAt = block.at + block.length - 4;
        putLittle(&bytes[sumAt], 4, lookup3(&bytes[block.at], block.length - 4));
        out.emplace_back(name, std::move(bytes));
        return;
      }
    }
  };
  constexpr std::uint64_t kPast = std::uint64_t{1} << 40;  // an address or size past the file
  auto chunked = [](const std::uint8_t* b) { return b[1] == 2; };  // layout class 2
  auto hard = [](const std::uint8_t* b) { return b[0] == 1 && (b[1] & 0x08) == 0; };
  add("a link message's version", 0x06, 0, 1, 0x7f, 2);
  add("a link's name length past its message", 0x06, 2, 1, 0xff, 3, 0, hard);
  add("a hard link's address past the file", 0x06, 3, 8, kPast, 12, 0,
      [](const std::uint8_t* b) { return b[0] == 1 && b[1] == 0; });
  add("a dataspace's first dimension of 2^40", 0x01, 4, 8, kPast, 12, 0x08);
  add("a layout's chunk dimension of 2^31", 0x08, 5, 4, 0x80000000u, 9, 0, chunked);
  add("a layout's class made compact, without data", 0x08, 1, 3, 0, 4, 0, chunked);
  add("a layout of version 1", 0x08, 0, 1, 1, 2);
  add("a datatype's size of 0", 0x03, 4, 4, 0, 8);
  add("a datatype's size of 2^31", 0x03, 4, 4, 0x80000000u, 8);
  add("a filter pipeline of 255 filters", 0x0B, 1, 1, 0xff, 2);
  add("an attribute's name size past its message", 0x0C, 2, 2, 0xffff, 8);
  add("an attribute's dataspace size past its message", 0x0C, 6, 2, 0xffff, 8);
  add("link info's dense storage address at 0", 0x02, 2, 8, 0, 18);
  add("attribute info's dense storage address at 0", 0x15, 2, 8, 0, 18);
  add("a continuation's length of 2^40", 0x10, 8, 8, kPast, 16);
  add("a continuation's address past the file", 0x10, 0, 8, kPast, 16);
  // The shared flag is in the message's header, not its body.
  for (const Block& block : blocks_) {
    if (block.kind != "OHDR" || block.messages.empty()) continue;
    const auto m = std::find_if(block.messages.begin(), block.messages.end(),
                                [](const Message& x) { return x.type == 0x01; });
    if (m == block.messages.end()) continue;
    Bytes bytes = file_;
    bytes[m->at + 3] |= 0x02;
    putLittle(&bytes[block.at + block.length - 4], 4,
              lookup3(&bytes[block.at], block.length - 4));
    out.emplace_back("a dataspace message flagged shared", std::move(bytes));
    break;
  }
  // Global heap objects (no checksum): the first string object's size and index.
  for (const Block& block : blocks_) {
    if (block.kind != "GCOL" || block.messages.empty()) continue;
    const Message& m = block.messages.front();
    Bytes bytes = file_;
    putLittle(&bytes[m.at + 8], 8, kPast);
    out.emplace_back("a global heap object's size of 2^40", bytes);
    bytes = file_;
    putLittle(&bytes[m.at], 2, 0x7fff);
    out.emplace_back("a global heap object's index changed", std::move(bytes));
    break;
  }
  return out;
}

std::string CacheMutator::describe() const {
  std::size_t headers = 0, messages = 0, other = 0, heaps = 0;
  for (const Block& b : blocks_) {
    if (b.kind == "OHDR" || b.kind == "OCHK")
      ++headers, messages += b.messages.size();
    else if (b.kind == "GCOL")
      ++heaps;
    else
      ++other;
  }
  return std::to_string(headers) + " object header chunks (" + std::to_string(messages) +
         " messages), " + std::to_string(other) + " other checksummed blocks, " +
         std::to_string(heaps) + " global heap collections";
}

}  // namespace sph::fuzz
