#include "job/CacheRain.h"

#include "io/cache/RainCache.h"

namespace sph::job {

void showCachedRain(render::rain::SceneRain& rain, const io::CacheReader& reader, std::size_t frame,
                    double time, const Particles& fluid) {
  const io::CacheSummary& s = reader.summary();
  if (frame < s.frames.size() && s.frames[frame].rainDrops == rain.system().desc().count) {
    const io::RainFrame drops = io::readRainFrame(reader, frame);
    rain.restore(drops.time, drops.positions, drops.generations);
    return;
  }
  rain.advanceTo(time, fluid);
}

}  // namespace sph::job
