// Damaged copies of a real cache for the cache fuzzer (fuzz/fuzz_cache.cpp): byte flips,
// truncations and zero-filled ranges anywhere, and changed fields of HDF5's own metadata (object
// header messages: dataspace dimensions, datatype and attribute sizes, chunk sizes and
// addresses, link names, continuations; B-tree, fixed array and heap blocks; global heap
// objects), written back with a valid checksum where the block has one, so that HDF5 reads the
// changed field instead of refusing the block.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace sph::fuzz {

using Bytes = std::vector<std::uint8_t>;

class CacheMutator {
 public:
  // Finds the metadata blocks of `file` (a cache's bytes), by signature and checksum.
  explicit CacheMutator(Bytes file);

  // A damaged copy, and a few words on what was changed ("flip 2 bytes at 81234", "OHDR at 34000,
  // message 0x08 +12: 4 bytes = 0xffffffff, checksum kept").
  Bytes mutate(std::mt19937_64& random, std::string& what) const;

  // The corpus of mutated metadata: one named damage per kind of field HDF5 trusts (a link's
  // version, name length and address; a dataspace's dimension; a chunk's dimension; a layout's
  // class and version; a datatype's size; a shared-message flag; a filter pipeline's count; an
  // attribute's name size; dense-storage addresses; a continuation's length; a global heap
  // object's size and index), each at the first place of the file that has it, checksum kept.
  // The same kinds on every machine, whatever offsets the cache's bytes have there.
  std::vector<std::pair<std::string, Bytes>> corpus() const;

  // The blocks found, for the harness's first line: "61 object header chunks (612 messages),
  // 14 other checksummed blocks, 3 global heap collections".
  std::string describe() const;

 private:
  struct Message {
    std::size_t at = 0;      // its 4- or 6-byte message header (a global heap object's 16)
    std::size_t prefix = 0;  // that header's bytes: the body is at at + prefix
    std::size_t size = 0;    // header and body
    unsigned type = 0;
  };
  struct Block {
    std::size_t at = 0, length = 0;  // the checksum is the block's last 4 bytes, if it has one
    bool checksummed = true;
    std::string kind;               // "OHDR", "OCHK", "BTHD", "GCOL", ...
    std::vector<Message> messages;  // object header chunks only
  };

  void findObjectHeaders();
  void findOtherBlocks();
  void findHeapCollections();
  void mutateMetadata(Bytes& bytes, std::mt19937_64& random, std::string& what) const;

  Bytes file_;
  std::size_t base_ = 0;  // the superblock's offset: the user block's size
  std::vector<Block> blocks_;
};

}  // namespace sph::fuzz
