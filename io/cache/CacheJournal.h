// A one-entry undo journal for the one write of a cache commit that a kill could tear.
//
// Committing a frame rewrites the root group's object header in place with one write() call
// (io/cache/CacheCommit.cpp). Linux can cut a write that spans several memory pages short when SIGKILL
// arrives in the middle of it: the header would then be part new, part old, its checksum would
// fail and HDF5 could not open the file at all. So before each such commit the writer copies the
// header as it is on disk (the last committed state) into the file's user block, the space HDF5
// leaves free at the start of the file. If a reader finds a header that fails HDF5's checks, it
// puts the copy back, which returns the file to its last commit (the interrupted frame is lost,
// every committed one is kept), and opens it again.
//
// Record, at file offset 0:
//   "SPHJRNL1" | u64 file offset of the image | u64 length | u32 CRC-32 of the image |
//   u32 CRC-32 of the preceding 28 bytes | image
// A torn journal write fails its CRCs and is ignored; it can only be torn before the commit's
// flush began, when the header on disk is still whole.
#pragma once

#include <cstdint>
#include <string>

namespace sph::io::cache {

// Room for the record in a user block of `userBlockBytes`: the largest image it can hold.
std::uint64_t journalCapacity(std::uint64_t userBlockBytes);

// Copies `length` bytes at `offset` of the open file `fd` into the journal at the file's start.
// Returns false (writing nothing) if they do not fit in `userBlockBytes`; throws InputError if
// they cannot be read or the journal cannot be written (a full disk: the user block is a hole
// until first written), for a commit without its journal must not go ahead.
bool journalRegion(int fd, std::uint64_t offset, std::uint64_t length,
                   std::uint64_t userBlockBytes);

// Reader side: if `path` holds a valid journal whose image differs from the bytes now at its
// offset, writes the image back and returns true, after saving the replaced bytes so that
// undoRepair() can put them back if the repair did not help. Throws InputError if the file is
// not writable. Returns false when there is nothing to restore.
struct JournalRepair {
  std::string path;
  std::uint64_t offset = 0;
  std::string replaced;  // the bytes the repair overwrote
};
bool repairFromJournal(const std::string& path, JournalRepair& repair);
void undoRepair(const JournalRepair& repair);

}  // namespace sph::io::cache
