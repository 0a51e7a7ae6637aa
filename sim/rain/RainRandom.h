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

inline std::uint64_t hash4(std::uint64_t seed, std::uint64_t drop, std::uint64_t generation,
                           std::uint64_t draw) {
  std::uint64_t h = mix64(seed + 0x9e3779b97f4a7c15ULL);
  h = mix64(h ^ (drop + 0x632be59bd9b4e019ULL));
  h = mix64(h ^ (generation * 0x85157af5ULL + draw + 0x1b873593ULL));
  return h;
}

// Uniform in [0, 1): the top 24 bits, exact in a float.
inline float unitRandom(std::uint64_t seed, std::uint64_t drop, std::uint64_t generation,
                        std::uint64_t draw) {
  return static_cast<float>(hash4(seed, drop, generation, draw) >> 40) * (1.0f / 16777216.0f);
}

}  // namespace sph::rain
