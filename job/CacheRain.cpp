#include "job/CacheRain.h"

#include "io/cache/RainCache.h"

namespace sph::job {

void showCachedRain(render::rain::SceneRain& rain, const io::cache::CacheReader& reader,
                    std::size_t frame, double time, const Particles& fluid) {
  const io::cache::CacheSummary& s = reader.summary();
  if (frame < s.frames.size() && s.frames[frame].rainDrops == rain.system().desc().count) {
    const io::cache::RainFrame drops = io::cache::readRainFrame(reader, frame);
    rain.restore(drops.time, drops.positions, drops.generations);
    return;
  }
  rain.advanceTo(time, fluid);
}

}  // namespace sph::job
