// The suite of the cache commands as a user meets them (test_cache_cli, test_cache_cli_paths,
// test_cache_cli_damage): each program writes the tiny scene's cache once (TinyCacheSuite) and
// runs the binary on it and beside it.
#pragma once

#include <string>

#include "tests/CacheTestSupport.h"

namespace sph::test {

// `sphsplat ARGS` as a shell command for runShell (sphsplatShell).
inline std::string sphsplat(const std::string& args) {
  return sphsplatShell(args);
}

class CacheCli : public TinyCacheSuite {};

}  // namespace sph::test
