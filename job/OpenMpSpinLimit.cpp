#include "job/OpenMpSpinLimit.h"

#include <unistd.h>

#include <cstdlib>
#include <string>

namespace sph::job {

bool openMpSpinUnset() {
  return !std::getenv("OMP_WAIT_POLICY") && !std::getenv("GOMP_SPINCOUNT");
}

void relaunchWithOpenMpSpinLimit(char** argv) {
  if (!openMpSpinUnset()) return;
  if (setenv("GOMP_SPINCOUNT", kOpenMpSpinCount, 0) != 0) return;
  // /proc/self/exe: the binary itself, whatever argv[0] says (a relative path, a PATH lookup).
  execv("/proc/self/exe", argv);
}

const char* describeOpenMpWaiting() {
  static std::string text;
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  if (spin && std::string(spin) == kOpenMpSpinCount && !policy) {
    text = std::string("idle spinning capped (GOMP_SPINCOUNT=") + kOpenMpSpinCount +
           "; set GOMP_SPINCOUNT or OMP_WAIT_POLICY to choose)";
  } else {
    text = std::string("idle waiting as set (") +
           (policy ? std::string("OMP_WAIT_POLICY=") + policy : std::string("")) +
           (policy && spin ? " " : "") + (spin ? std::string("GOMP_SPINCOUNT=") + spin : "") + ")";
  }
  return text.c_str();
}

}  // namespace sph::job
