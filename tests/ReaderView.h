// Part of the preload library of the cache tests (KillAtWrite.cpp): with
// SPHSPLAT_READER_VIEW_LOG=PATH set, it checks after every call that changes a published cache
// (`run.h5`, not `run.h5.partial`, which no reader opens) what a reader that opened the file at
// that moment could meet, and adds a line to PATH for each call that breaks one of the rules a
// reader relies on (docs/cache-format.md, "Reading while a run writes"):
//
// 1. The file is at least as long as its superblock says (HDF5's end-of-file address), so the
//    open does not fail with "truncated file". (HDF5's reader takes the size a moment before it
//    reads the superblock; the margin the writer grows the file by for that moment is not
//    checked here but by the reading loop of tests/test_cache_concurrent.cpp.)
// 2. Nothing a reader may read after its open changes in place: once the root header links an
//    object, every later write below the end of the file as it was then either leaves the bytes
//    as they were or goes to the user block (the journal), the superblock or the root group's
//    header, which a reader loads once, when it opens the file.
#pragma once

#include <cstddef>

namespace sph::test::readerview {

// `path` is the file behind the descriptor; `data`/`bytes` at `offset` what is about to be
// written. `call` numbers the calls for the log.
void beforeWrite(const char* path, int fd, const void* data, std::size_t bytes, long long offset,
                 long call);
// After a write or a truncation of that file.
void afterChange(const char* path, int fd, long call);

}  // namespace sph::test::readerview
