#include "job/CacheScene.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "job/ExitCode.h"
#include "io/MessageText.h"
#include "io/scene/SceneLoader.h"
#include "sim/InputError.h"

namespace sph::job {

void checkPositions(const std::vector<float>& x, const std::vector<float>& y,
                    const std::vector<float>& z, const scene::Scene& scene, const std::string& what,
                    const std::string& path) {
  // A spacing of slack: a particle is removed once it is past the domain's face.
  const float slack = scene.solver.spacing;
  const bool bounded = !scene.domain.empty();
  const std::vector<float>* axes[3] = {&x, &y, &z};
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < axes[a]->size(); ++i) {
      const float v = (*axes[a])[i];
      if (std::isfinite(v) && (!bounded || (v >= scene.domain.lo[a] - slack &&
                                            v <= scene.domain.hi[a] + slack)))
        continue;
      std::ostringstream s;
      s << path << ": damaged cache: " << what << " has particle " << i << " at "
        << "xyz"[a] << " = " << v << " m, ";
      if (bounded)
        s << "outside the scene's domain (" << scene.domain.lo[a] << " to " << scene.domain.hi[a]
          << " m)";
      else
        s << "not a number";
      throw InputError(s.str());
    }
  }
}

scene::Scene sceneOfCache(const io::cache::CacheSummary& summary,
                          const std::vector<std::string>& extraEdits) {
  std::vector<std::string> edits = io::cache::sceneEdits(summary);
  edits.insert(edits.end(), extraEdits.begin(), extraEdits.end());
  try {
    return io::scene::parseScene(summary.sceneText, summary.scenePath, edits);
  } catch (const InputError& e) {
    throw InputError(summary.path + ": the scene recorded in the cache: " + e.what());
  }
}

namespace {

long long parseIndex(const std::string& text, std::size_t frames, const std::string& flag) {
  if (text == "last" || text == "-1") return static_cast<long long>(frames) - 1;
  std::size_t used = 0;
  long long v = -1;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || v < 0) {
    throw InputError(flag + ": expected a frame index (0, 1, ...), 'last' or -1, got '" +
                     io::printable(text) + "'");
  }
  return v;
}

}  // namespace

std::vector<std::size_t> parseFrameRange(const std::string& text, std::size_t frames,
                                         const std::string& flag) {
  if (frames == 0) throw InputError(flag + ": the cache has no complete frame");
  long long first = 0, last = static_cast<long long>(frames) - 1;
  const std::size_t colon = text.find(':');
  if (text == "all") {
    // every frame
  } else if (colon == std::string::npos) {
    first = last = parseIndex(text, frames, flag);
  } else {
    if (colon > 0) first = parseIndex(text.substr(0, colon), frames, flag);
    if (colon + 1 < text.size()) last = parseIndex(text.substr(colon + 1), frames, flag);
  }
  if (first > last) {
    throw InputError(flag + ": frames " + io::printable(text) +
                     " run backwards (write the first frame first, " + std::to_string(last) + ":" +
                     std::to_string(first) + ")");
  }
  if (last >= static_cast<long long>(frames)) {
    throw InputError(flag + ": frames " + io::printable(text) +
                     " are not in the cache (it has frames 0 to " + std::to_string(frames - 1) +
                     ")");
  }
  std::vector<std::size_t> out;
  for (long long f = first; f <= last; ++f) out.push_back(static_cast<std::size_t>(f));
  return out;
}

std::size_t parseOneFrame(const std::string& text, std::size_t frames, const std::string& flag) {
  const std::vector<std::size_t> range = parseFrameRange(text, frames, flag);
  if (range.size() != 1) {
    throw InputError(flag + ": expected one frame (an index, 'last' or -1), got the range '" +
                     io::printable(text) + "'");
  }
  return range.front();
}

std::string damageLine(const io::cache::CacheSummary& summary) {
  if (summary.damagedFrame.empty()) return "";
  const std::size_t n = summary.frames.size();
  return "sphsplat: " + io::printablePath(summary.path) + ": damaged cache: frame " +
         std::to_string(n) + " does not read back (" + io::printable(summary.damagedFrame, 160) +
         ")" + (n ? "; frames 0-" + std::to_string(n - 1) + " are complete" : "");
}

int exitAfterReading(const io::cache::CacheSummary& summary) {
  const std::string line = damageLine(summary);
  if (line.empty()) return kOk;
  std::fflush(stdout);
  std::fprintf(stderr, "%s\n", io::oneLine(line).c_str());
  return kBadInput;
}

}  // namespace sph::job
