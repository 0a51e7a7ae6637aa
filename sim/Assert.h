// Bug checks (STYLE.md rule 10). SPH_ASSERT is on in debug builds; SPH_VALIDATE guards the heavier
// whole-state checks and is switched on by the CMake option SPHSPLAT_VALIDATE.
#pragma once

#include <cstdio>
#include <cstdlib>

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
