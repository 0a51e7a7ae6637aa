// What `sphsplat render CACHE` does once its flags are parsed: the cached frames drawn with point
// or quad splats (and the scene's solids, lights and rain) into PNGs and, with --to-cache, into
// the cache. No simulation: the particles come from the cache.
#pragma once

#include <string>
#include <vector>

namespace sph::job {

struct RenderRequest {
  std::string cache;
  std::string frames = "0:";
  std::string splat;  // empty: the scene's render.splat
  std::string size;   // empty: the scene's render size
  std::string out = "results/render";
  bool toCache = false;
  bool quiet = false;
  std::vector<std::string> overrides;
};

// Returns the process's exit code (job/ExitCode.h).
int renderJob(const RenderRequest& request);

}  // namespace sph::job
