// The rain of a cache's frame in `render` and `view` (docs/rain.md, "Replay"): the drops the run
// stored beside the frame (/Rain#N, io/cache/RainCache.h), or, for a cache written without them (before
// the drops were stored), the drops regenerated from the scene up to the frame's time.
#pragma once

#include <cstddef>

#include "io/cache/CacheReader.h"
#include "render/rain/SceneRain.h"
#include "sim/Particles.h"

namespace sph::job {

void showCachedRain(render::rain::SceneRain& rain, const io::cache::CacheReader& reader,
                    std::size_t frame, double time, const Particles& fluid);

}  // namespace sph::job
