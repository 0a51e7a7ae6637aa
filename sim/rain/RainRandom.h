// Counter-based random numbers for rain (docs/rain.md): every number is a pure function of
// (seed, drop, respawn generation, draw), so drops are spawned in parallel, in any order, with
// bit-identical results for a seed - the paper's Table 1 compares stateful generators instead.
#pragma once

#include <cstdint>

namespace sph::rain {

// SplitMix64's finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mix.
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The part of hash4 that depends on (seed, drop) alone.
inline std::uint64_t dropKey(std::uint64_t seed, std::uint64_t drop) {
  return mix64(mix64(seed + 0x9e3779b97f4a7c15ULL) ^ (drop + 0x632be59bd9b4e019ULL));
}

inline std::uint64_t hash4(std::uint64_t seed, std::uint64_t drop, std::uint64_t generation,
                           std::uint64_t draw) {
  return mix64(dropKey(seed, drop) ^ (generation * 0x85157af5ULL + draw + 0x1b873593ULL));
}

// Uniform in [0, 1): the top 24 bits, exact in a float.
inline float unitOf(std::uint64_t hash) {
  return static_cast<float>(hash >> 40) * (1.0f / 16777216.0f);
}

inline float unitRandom(std::uint64_t seed, std::uint64_t drop, std::uint64_t generation,
                        std::uint64_t draw) {
  return unitOf(hash4(seed, drop, generation, draw));
}

// unitRandom(seed, drop, generation, draw) for one (seed, drop, generation) and many draws, with
// the (seed, drop) part mixed once: a respawn takes ~8 numbers, and two of the three mixes per
// number were this same part (the `view` update at 1,000,000 drops respawns most of them).
class DropRandom {
 public:
  DropRandom(std::uint64_t seed, std::uint64_t drop, std::uint64_t generation)
      : key_(dropKey(seed, drop)), offset_(generation * 0x85157af5ULL + 0x1b873593ULL) {}
  float operator()(std::uint64_t draw) const { return unitOf(bits(draw)); }
  // The whole 64-bit hash of a draw (sim/rain/ViewSampler.h takes a point of a cube from it).
  std::uint64_t bits(std::uint64_t draw) const { return mix64(key_ ^ (offset_ + draw)); }
  // What bits() mixes, for the same hash in SIMD lanes: mix64(key() ^ (offset() + draw)).
  std::uint64_t key() const { return key_; }
  std::uint64_t offset() const { return offset_; }

 private:
  std::uint64_t key_, offset_;
};

}  // namespace sph::rain
