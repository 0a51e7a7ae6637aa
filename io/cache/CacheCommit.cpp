// The commit of io/CacheWriter: how a frame (or an image, or a status) becomes part of the cache so
// that a process killed at any moment leaves every committed frame readable.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "io/cache/CacheJournal.h"
#include "io/cache/CacheWriter.h"
#include "sim/InputError.h"

namespace sph::io::cache {
namespace {

using h5::check;

// How far ahead of HDF5's end of allocation the file is grown during a run (commitObjects).
constexpr std::uint64_t kGrowthMargin = 1 << 20;

}  // namespace

// Commits what was written since the last commit. HDF5 1.10 has no transactions, and kill -9 can
// strike between any two of its write() calls, so the cache is written so that every such moment
// leaves a file whose committed frames read back exactly:
//
// 1. A frame's objects are created anonymous (H5Gcreate_anon): nothing the file already links
//    refers to them. commitObjects() writes them out (H5Fflush) while the file on disk still
//    shows the previous state. Dying here leaves unreferenced bytes past the old data.
// 2. Only then are they linked into the root (H5Olink) and committed again. The root's links
//    live in its object header ("compact" storage) which was sized at creation for the expected
//    frames, so the link lands in free space of the header's one block and the flush rewrites
//    that block with a single write(): the file shows the new frame or the old state (a write
//    cut short: point 6). The header carries a checksum, so a mix is never misread as data.
// 3. The metadata cache may evict (write) dirty entries before a flush; between commits the only
//    dirty entries are the new, unlinked objects, so such early writes land in new space. And
//    space never comes from freed blocks (file space strategy NONE, Hdf5.cpp): new data cannot
//    overwrite anything the last committed state still points to.
// 4. Before each flush the file is grown past HDF5's end-of-allocation address (EOA): the
//    superblock written by the flush records the EOA and a reader refuses a file shorter than
//    that ("truncated file"). A reader takes the file's size when it opens it and reads the
//    superblock a moment later, so a margin (kGrowthMargin) keeps the size ahead of the EOA of
//    the commits that may come in between; close() cuts it off. Datasets are flushed before
//    (writeDataset, writeRenderedFrame): the EOA read here is the one the flush records.
// 5. Superblock version 2 (the 1.8 format) has no "open for writing" flag, so the killed file
//    opens without h5clear.
// 6. The one in-place write of step 2 can still be cut short at a page boundary by SIGKILL;
//    `rewritten` (the header that commit rewrites) is first copied to the journal
//    (CacheJournal.h), from which a reader restores it.
// 7. For readers while the run goes on: what changes in place is only the user block, the
//    superblock and the header of the root, which a reader reads when it opens the file; every
//    object the root links is written before and never changes after (the one header rewrite
//    at link time, H5Olink, writes the same bytes again). So a reader sees the file as it was at
//    its open, for as long as it keeps it open.
// tests/test_cache_crash.cpp kills the writer at every write() of a run, and also tears each
// write that spans pages, and checks 1-6; tests/test_cache_concurrent.cpp checks 4 and 7 after
// every write of a rendering run, and reads the cache in a loop while it is written.
//
// All ranks writing a frame together (slice_, parallel HDF5 over MPI-IO) keep every point: the
// flush is collective, rank 0 (the one with fd_) grows the file and writes the journal before it
// and the others wait for that; after it they wait for each other, so that every rank's writes of
// the objects are done before any rank writes the header that links them (point 2). A rank
// killed at any moment leaves the file as a killed single process would (tests/test_mpi.cpp).
void CacheWriter::commitObjects(hid_t rewritten) {
  growFile();
  if (rewritten >= 0) journalHeader(rewritten);
  if (slice_) slice_->ranks->allGather({});  // a barrier: the file is grown, the journal written
  check(H5Fflush(file_.get(), H5F_SCOPE_LOCAL), "flush the cache");
  if (slice_) slice_->ranks->allGather({});  // every rank's part of this commit is written
  // HDF5 cuts the file to its end of allocation after a flush when the last block it allocated
  // is not written yet (a global heap block, an image's chunk): restore the margin before the
  // next superblock is written.
  growFile();
}

void CacheWriter::growFile() {
  if (fd_ < 0) return;  // a rank other than 0 writing a frame together with it
  if (slice_) {
    // Over MPI-IO: to the frame's bound (CacheFrames.cpp, writeFrame), as the end of allocation
    // cannot be read there.
    struct stat st {};
    if (fstat(fd_, &st) != 0) throw h5::Error("stat the cache", std::strerror(errno));
    if (static_cast<std::uint64_t>(st.st_size) < frameEnd_ &&
        ftruncate(fd_, static_cast<off_t>(frameEnd_)) != 0) {
      throw h5::Error("grow the cache file", std::strerror(errno));
    }
    return;
  }
  haddr_t eoa = 0;
  check(H5Fget_eoa(file_.get(), &eoa), "read the end of allocation");
  struct stat st {};
  if (fstat(fd_, &st) != 0) throw h5::Error("stat the cache", std::strerror(errno));
  // H5Fget_eoa gives a file offset (the user block included), which is what the superblock
  // records and what a reader compares with the file's size. The margin is a hole in the file:
  // it takes no disk space.
  const auto size = static_cast<std::uint64_t>(st.st_size), end = static_cast<std::uint64_t>(eoa);
  if (size < end + kGrowthMargin / 2 &&
      ftruncate(fd_, static_cast<off_t>(end + kGrowthMargin)) != 0) {
    throw h5::Error("grow the cache file", std::strerror(errno));
  }
}

void CacheWriter::journalHeader(hid_t object) {
  H5O_info_t info;
  check(H5Oget_info2(object, &info, H5O_INFO_BASIC | H5O_INFO_HDR), "read an object header's size");
  // Rank 0 journals for all ranks writing together (the others read the header all the same: the
  // ranks' HDF5 calls must be alike, CacheFrames.cpp).
  if (fd_ < 0) return;
  // A header of one block, as the root is sized to stay (more blocks would be more writes).
  if (info.hdr.nchunks != 1 || userBlock_ == 0) return;
  try {
    journalRegion(fd_, userBlock_ + info.addr, info.hdr.space.total, userBlock_);
  } catch (const InputError& e) {
    throw h5::Error(e.what(), "");  // said as the commit's other failures are
  }
}

}  // namespace sph::io::cache
