// Bug checks (STYLE.md rule 10). SPH_ASSERT is on in debug builds; SPH_VALIDATE guards the heavier
// whole-state checks (sim/solver/Validate.h) and is switched on by the CMake option SPHSPLAT_VALIDATE
// (on in the sanitize preset, so `scripts/test --sanitize` runs every test with them).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

#ifndef NDEBUG
#define SPH_ASSERT(cond)                                                                         \
  do {                                                                                           \
    if (!(cond)) {                                                                               \
      std::fprintf(stderr, "%s:%d: internal error: assertion '%s' failed\n", __FILE__, __LINE__, \
                   #cond);                                                                       \
      std::abort();                                                                              \
    }                                                                                            \
  } while (0)
#else
#define SPH_ASSERT(cond) ((void)0)
#endif

#ifndef SPH_VALIDATE
#define SPH_VALIDATE 0
#endif

namespace sph {

// Runs check() (returning "" when the invariant holds, else what is wrong) in builds with
// SPH_VALIDATE, and stops the process with one "internal error" line naming `where` if it fails.
// In other builds neither the check nor its arguments cost anything.
template <class Check>
void validate(const char* where, Check&& check) {
  if constexpr (SPH_VALIDATE != 0) {
    const std::string problem = check();
    if (!problem.empty()) {
      std::fprintf(stderr, "internal error: validation failed after %s: %s\n", where,
                   problem.c_str());
      std::abort();
    }
  } else {
    (void)where, (void)check;
  }
}

}  // namespace sph
