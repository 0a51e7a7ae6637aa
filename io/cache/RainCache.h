// The rain's drops in the cache (docs/cache-format.md, "Rain drops: /Rain#N"; docs/rain.md): a
// second particle set beside each frame of a scene with a rain section, so ParaView shows the
// drops through the XDMF sidecar, `info` counts them, `render`/`view` redraw them and a resume
// continues them exactly. Written with CacheWriter's two-phase commit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/CacheWriter.h"
#include "sim/rain/RainSystem.h"

namespace sph::io::cache {

struct RainFrame {
  double time = 0;  // s, the frame's
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> generations;  // respawns per drop (RainSystem::generations)
  std::vector<std::uint8_t> layers;        // streak image per drop
};

// Stores the drops of `rain` as /Rain#<frame> (frame `frame` must be written).
void writeRainFrame(CacheWriter& writer, std::size_t frame, double time,
                    const rain::RainSystem& rain);
// The drops stored for `frame`; throws InputError if the cache has none for it.
RainFrame readRainFrame(const CacheReader& reader, std::size_t frame);

}  // namespace sph::io::cache
