// The lock a writing run holds on its cache file itself (docs/cache-format.md, "Crash safety"),
// beside io/OutputLock's lock file that is taken before anything is created.
#pragma once

#include <string>

namespace sph::io::cache {

// Takes an exclusive advisory lock (open file description lock, which HDF5's own flock()
// ignores) on one byte of `path` far past its data (CacheFileLock.cpp says why not the whole
// file) and returns its descriptor; throws InputError naming the file if another
// sphsplat run holds it.
int lockCacheFile(const std::string& path);
// Whether a sphsplat run holds that lock on `path` now (a run is writing it).
bool cacheIsLocked(const std::string& path);

}  // namespace sph::io::cache
