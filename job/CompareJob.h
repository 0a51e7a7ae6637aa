// What `sphsplat compare CACHE --frame N` does once its flags are parsed: point splats, quad
// splats and the ray-marched reference of one cached frame side by side, with their times and
// error figures, and with a scene's particle lights the light through each filter beside the
// exact sum (docs/rendering.md, docs/lights.md).
#pragma once

#include <string>
#include <vector>

namespace sph::job {

struct CompareRequest {
  std::string cache;
  std::string frame = "last";
  std::string out = "results/compare";
  std::string size = "640x480";
  std::vector<std::string> overrides;
};

// Returns the process's exit code (job/ExitCode.h).
int compareJob(const CompareRequest& request);

}  // namespace sph::job
