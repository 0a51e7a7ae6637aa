// The scene a cache was made from, rebuilt from the text and the --set edits the cache records
// (so a cache renders the same on a machine without the scene file), plus a reader's extra edits.
#pragma once

#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "sim/scene/Scene.h"

namespace sph::job {

scene::Scene sceneOfCache(const io::cache::CacheSummary& summary,
                          const std::vector<std::string>& extraEdits);

// Positions read from the cache at `path` (frame `frame`'s particles, or its boundary when
// `frame` is "the boundary") as a run leaves them: finite and inside the scene's domain (a run
// removes the particles that leave it). A damaged array is one InputError line instead of a
// lattice over an absurd box. Throws InputError.
void checkPositions(const std::vector<float>& x, const std::vector<float>& y,
                    const std::vector<float>& z, const scene::Scene& scene, const std::string& what,
                    const std::string& path);

// The one frame syntax of every subcommand (render, compare, view, export): "7", "last", "-1"
// (the last), "2:9" (inclusive), "3:", ":4" and "all" over a cache of `frames` frames. Throws
// InputError naming the flag.
std::vector<std::size_t> parseFrameRange(const std::string& text, std::size_t frames,
                                         const std::string& flag);
// The same syntax where one frame is meant (compare, view): a range of several is refused.
std::size_t parseOneFrame(const std::string& text, std::size_t frames, const std::string& flag);

// A cache whose frames stop at one that does not read back: "PATH: damaged cache: frame N does
// not read back (WHAT); frames 0-M are complete" ("" when none does). Its frames are the complete
// ones, so "all" and "last" mean those: a command that read it says so after its work.
std::string damageLine(const io::cache::CacheSummary& summary);
// Prints damageLine() to stderr and returns the exit code of a command that has done what the
// complete frames let it: 2 (bad input) for a damaged cache, else 0.
int exitAfterReading(const io::cache::CacheSummary& summary);

}  // namespace sph::job
