// What rain.feed_fluid has added to the fluid so far (sim/rain/RainFeed.h): part of a run's state,
// apart from the feed itself so that the run state does not need the rain's machinery.
#pragma once

#include <cstdint>

namespace sph::rain {

// What a feeding rain has put into the fluid; part of the run's state (RunState::rain), so a
// resume continues it exactly. Mass is conserved to round-off:
// landedDrops * drop_volume == particles * spacing^3 + pending.
struct FeedState {
  std::uint64_t landedDrops = 0;  // drops that landed in the water, cumulative
  std::uint64_t particles = 0;    // fluid particles made of them, cumulative
  double pending = 0;  // m^3 of landed water not yet a particle: less than one particle's worth
};

}  // namespace sph::rain
