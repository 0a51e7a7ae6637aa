// main() of the GL suites (label `gl`): runs the tests on the machine's OpenGL.
//
// Under AddressSanitizer the suites end with _exit, which skips LeakSanitizer's exit check: Mesa
// llvmpipe keeps about 100 bytes per context that ran a transform feedback draw until the process
// ends, allocated from JIT code that LeakSanitizer can neither symbolise nor suppress by module.
// Our own GL code owns every object through RAII handles (render/gl/GlHandle.h); the CPU suites
// keep the leak check.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
#if defined(__SANITIZE_ADDRESS__)
  std::fflush(nullptr);
  _exit(result);
#endif
  return result;
}
