#include "app/OpenMpSpinLimit.h"

#include <unistd.h>

#include <cstdlib>

namespace sph::app {

bool openMpSpinUnset() {
  return !std::getenv("OMP_WAIT_POLICY") && !std::getenv("GOMP_SPINCOUNT");
}

void relaunchWithOpenMpSpinLimit(char** argv) {
  if (!openMpSpinUnset()) return;
  if (setenv("GOMP_SPINCOUNT", kOpenMpSpinCount, 0) != 0) return;
  // /proc/self/exe: the binary itself, whatever argv[0] says (a relative path, a PATH lookup).
  execv("/proc/self/exe", argv);
}

}  // namespace sph::app
