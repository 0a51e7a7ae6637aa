// Drops placed uniformly in the rain space of spawn "view" with sampling "uniform" (docs/rain.md,
// "How `uniform` places a drop"): candidates uniform in a region around the rain space, the
// first inside it kept. Points uniform in the region and kept where they are in the rain space
// are uniform in the rain space, whatever the region; it is chosen for the fewest candidates
// (RainSpace::drawsFromPyramid):
// - the sphere's bounding cube: uniform in the sphere of eq. (5) by rejection, then kept where
//   the side planes of eq. (8)-(9) say it is inside the frustum - the paper's "a random point of
//   the sphere, kept if inside the frustum" without its trigonometry and cube root. A candidate
//   is one 64-bit hash: 21 bits an axis. The sphere holds pi/6 of the cube, so at the 45-degree,
//   16:9 rain space a drop takes ~4 candidates (2.1 of them in the sphere): 16 are computed at
//   once in AVX-512 lanes where the build has AVX-512 F and DQ (64-bit multiplies for the hash),
//   one at a time otherwise, with the same bits either way.
// - the pyramid from the eye to the far plane, at narrow fields of view, where the rain space is
//   a needle that fills a tiny share of the cube (0.17% at 3 degrees, 16:9: 512 candidates missed
//   it for 41% of the drops) but most of the pyramid. Two hashes a candidate, one at a time.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sim/Types.h"
#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSpace.h"

namespace sph::rain {

#if defined(__AVX512F__) && defined(__AVX512DQ__)
inline constexpr bool kViewCandidatesInLanes = true;
#else
inline constexpr bool kViewCandidatesInLanes = false;
#endif

// 21 bits as one of 2^21 evenly spaced values in (-1, 1), symmetric about 0: the odd multiples
// of 2^-21 (exact in a float).
inline float cubeCoordinate(std::uint64_t bits21) {
  return static_cast<float>(static_cast<std::int32_t>(2 * bits21) - 0x1fffff) * (1.0f / 2097152.0f);
}

// 21 bits as one of 2^21 evenly spaced values in (0, 1): the odd multiples of 2^-22.
inline float unitCoordinate(std::uint64_t bits21) {
  return static_cast<float>(2 * bits21 + 1) * (1.0f / 4194304.0f);
}

// The point of the cube (-1, 1)^3 that a 64-bit hash gives: x from bits 0-20, y from 21-41, z from
// 42-62 (mix64's bits are equally good; bit 63 is not used).
inline Vec3 cubePoint(std::uint64_t hash) {
  return Vec3(cubeCoordinate(hash & 0x1fffff), cubeCoordinate((hash >> 21) & 0x1fffff),
              cubeCoordinate((hash >> 42) & 0x1fffff));
}

// A candidate: the point of the sphere's bounding cube, whether it is in the sphere, and whether
// it is in the rain space (sphere and side planes: RainSpace::contains, to the bit).
struct ViewCandidate {
  Vec3 p;
  bool inSphere, inside;
};

inline ViewCandidate viewCandidate(const RainSpace& s, std::uint64_t hash) {
  const Vec3 q = cubePoint(hash);
  const Vec3 p(std::fma(s.radius, q.x(), s.centre.x()), std::fma(s.radius, q.y(), s.centre.y()),
               std::fma(s.radius, q.z(), s.centre.z()));
  const bool sphere = s.insideSphere(p);
  return {p, sphere, sphere && s.insideSides(p)};
}

// A candidate of the pyramid from the eye to the far plane (to drawDepth), uniform in its volume,
// from two hashes: the depth is drawDepth times the largest of three numbers of `depth` (its
// density 3 m^2 grows as the pyramid's cross-section, z^2), the offsets along right and up uniform
// across that depth's rectangle from `across`. Points nearer than `near` are outside the sphere,
// which touches the near plane: the test of the sphere refuses them. Every sum rounded as written.
inline ViewCandidate pyramidCandidate(const RainSpace& s, std::uint64_t depth,
                                      std::uint64_t across) {
  const float m =
      std::max({unitCoordinate(depth & 0x1fffff), unitCoordinate((depth >> 21) & 0x1fffff),
                unitCoordinate((depth >> 42) & 0x1fffff)});
  const float z = s.drawDepth * m;
  const float x = z * s.tanRight * cubeCoordinate(across & 0x1fffff);
  const float y = z * s.tanUp * cubeCoordinate((across >> 21) & 0x1fffff);
  Vec3 p;
  for (int k = 0; k < 3; ++k)
    p[k] = std::fma(y, s.up[k], std::fma(x, s.right[k], std::fma(z, s.forward[k], s.eye[k])));
  const bool sphere = s.insideSphere(p);
  return {p, sphere, sphere && s.insideSides(p)};
}

// The candidates of draws first .. first + 15 of a drop's numbers: bit k of the masks is
// candidate k (draw first + k). Aligned to a cache line so that each 64-byte store of the lanes
// writes one line wherever the caller's frame puts it.
struct ViewCandidates16 {
  float x[16], y[16], z[16];
  std::uint32_t inSphere = 0, inside = 0;
};

// In AVX-512 lanes where kViewCandidatesInLanes, else viewCandidate 16 times: the same bits
// (RainSampling.CandidatesInSimdLanesAreTheOnesOneAtATime).
void viewCandidates16(const RainSpace& s, const DropRandom& u, std::uint64_t first,
                      ViewCandidates16& out);

// Candidates a spawn drew before the one it took (or all, when it took none).
struct ViewSpawnCount {
  std::uint64_t rejected = 0;       // in the sphere, refused by the side planes (eq. (8)-(9))
  std::uint64_t outsideSphere = 0;  // in the cube (or the pyramid), outside the sphere
  std::uint64_t parked = 0;         // spawns that found none free and parked (RainSystem)
};

// Places a drop: the first of `tries` candidates inside the rain space for which `free(p)` holds
// (outside the obstacles); false when none is. Draw 0 of `u` is the drop's streak image; the
// cube's candidate t is draw 1 + t, the pyramid's draws 1 + 2t and 2 + 2t.
// The first of `tries` candidates (`candidate(t)`, t = 0, 1, ...) inside the rain space and free,
// one at a time, counting those refused before it.
template <class Candidate, class Free>
bool firstFreeCandidate(int tries, const Candidate& candidate, const Free& free, Vec3& p,
                        ViewSpawnCount& count) {
  for (int t = 0; t < tries; ++t) {
    const ViewCandidate c = candidate(static_cast<std::uint64_t>(t));
    if (!c.inSphere) {
      ++count.outsideSphere;
    } else if (!c.inside) {
      ++count.rejected;
    } else if (free(c.p)) {
      p = c.p;
      return true;
    }
  }
  return false;
}

// spawnInView's candidates of the pyramid, out of line: the cube's path, which wide fields of view
// take, keeps the code it had without it.
template <class Free>
[[gnu::noinline]] bool spawnInPyramid(const RainSpace& s, const DropRandom& u, int tries,
                                      const Free& free, Vec3& p, ViewSpawnCount& count) {
  auto candidate = [&](std::uint64_t t) {
    return pyramidCandidate(s, u.bits(1 + 2 * t), u.bits(2 + 2 * t));
  };
  return firstFreeCandidate(tries, candidate, free, p, count);
}

template <class Free>
bool spawnInView(const RainSpace& s, const DropRandom& u, int tries, const Free& free, Vec3& p,
                 ViewSpawnCount& count) {
  if (s.drawsFromPyramid()) return spawnInPyramid(s, u, tries, free, p, count);
  if constexpr (kViewCandidatesInLanes) {
    ViewCandidates16 c;
    for (int first = 0; first < tries; first += 16) {
      viewCandidates16(s, u, 1 + static_cast<std::uint64_t>(first), c);
      const std::uint32_t valid = tries - first >= 16 ? 0xffffu : (1u << (tries - first)) - 1;
      std::uint32_t before = valid;  // the candidates drawn before the one taken
      bool found = false;
      for (std::uint32_t m = c.inside & valid; m != 0 && !found; m &= m - 1) {
        const int k = __builtin_ctz(m);
        const Vec3 q(c.x[k], c.y[k], c.z[k]);
        if (!free(q)) continue;
        p = q, found = true;
        before = (1u << k) - 1;
      }
      count.rejected += static_cast<unsigned>(__builtin_popcount(c.inSphere & ~c.inside & before));
      count.outsideSphere += static_cast<unsigned>(__builtin_popcount(~c.inSphere & before));
      if (found) return true;
    }
    return false;
  } else {
    auto candidate = [&](std::uint64_t t) { return viewCandidate(s, u.bits(1 + t)); };
    return firstFreeCandidate(tries, candidate, free, p, count);
  }
}

}  // namespace sph::rain
