// What `sphsplat run` does once its flags are parsed: load the scene, prepare the cache session
// and the pictures, run the frames (sim/run/RunLoop.h) with progress, and tell the user how it ended.
// The simulation, the loop and the cache session are libraries (sim/, io/); this is the wiring
// and the words.
#pragma once

#include <string>
#include <vector>

#include "io/cache/CacheSession.h"

namespace sph::app {

struct RunRequest {
  std::string scene;
  int threads = 0;  // 0: all cores
  double end = 0;   // s; 0: the scene's solver.end_time
  bool quiet = false;
  bool verbose = false;
  bool check = false;                  // --check: validate the scene and stop
  std::vector<std::string> overrides;  // --set KEY=VALUE
  io::CacheSessionOptions cache;
};

// Returns the process's exit code (app/ExitCode.h).
int runJob(const RunRequest& request);

}  // namespace sph::app
