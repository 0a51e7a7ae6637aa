#include "render/lights/CpuAccumulation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__F16C__) || defined(__x86_64__)
#include <immintrin.h>
#endif

#include "sim/Parallel.h"

namespace sph::render::lights {

std::uint16_t toHalf(float f) {
#ifdef __F16C__
  return static_cast<std::uint16_t>(_cvtss_sh(f, _MM_FROUND_TO_ZERO));
#else
  std::uint32_t x = 0;
  std::memcpy(&x, &f, sizeof x);
  const auto sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
  x &= 0x7fffffffu;
  if (x > 0x7f800000u) return sign | 0x7e00u;   // NaN
  if (x == 0x7f800000u) return sign | 0x7c00u;  // infinity
  if (x >= 0x47800000u) return sign | 0x7bffu;  // 65536 or more: the largest half, toward zero
  if (x < 0x38800000u) {                        // below 2^-14: a subnormal half, f 2^24 exactly
    float a = 0;
    std::memcpy(&a, &x, sizeof a);
    return sign | static_cast<std::uint16_t>(std::trunc(a * 16777216.0f));
  }
  // Rebias the exponent (127 - 15) and keep 10 of the 23 mantissa bits.
  return sign | static_cast<std::uint16_t>((x - 0x38000000u) >> 13);
#endif
}

namespace {

// std::llrint (to nearest, ties to even, in the default rounding mode) without the call into libm
// it compiles to here: six a light and voxel.
inline std::int64_t roundToInteger(float x) {
#ifdef __x86_64__
  return _mm_cvtss_si64(_mm_set_ss(x));
#else
  return std::llrint(x);
#endif
}

}  // namespace

void accumulateOnCpu(const LightsDesc& d, const std::vector<LightParticle>& lights,
                     const VoxelBox& box, float scale, const ViewCull* cull, VoxelSums& out) {
  out.touched = VoxelBox{};
  out.lights = cull ? 0 : lights.size();
  if (box.empty()) return;
  // The shader's loop: the voxel a light lies in and int(range / h) + 1 voxels either side.
  const int dist = static_cast<int>(d.range / d.voxelSize) + 1;
  auto voxelOf = [&](float x, int a) {
    return static_cast<int>(std::floor((x - d.origin[a]) / d.voxelSize));
  };
  // The voxels along axis a whose centres lie within range of x (one or two of the shader's three
  // when range < h; a thousandth of a voxel more for rounding, the distance test decides), inside
  // the shader's loop and the box. The voxels the shader visits beyond are all out of range.
  auto within = [&](float x, int a, int& lo, int& hi) {
    const std::size_t s = static_cast<std::size_t>(a);
    const float g = (x - d.origin[a]) / d.voxelSize - 0.5f, r = d.range / d.voxelSize + 1e-3f;
    const int c = voxelOf(x, a);
    lo = std::max({static_cast<int>(std::ceil(g - r)), c - dist, box.lo[s]});
    hi = std::min({static_cast<int>(std::floor(g + r)), c + dist, box.hi[s] - 1});
    return lo <= hi;
  };
  // The lights by the z slice they lie in (those the cull keeps that reach a voxel of the box
  // only), in their given order: each slice then visits its 2 dist + 1 neighbouring buckets.
  // Copied in that order, not indexed: a slice then reads them in a row, where indices into the
  // given order would fetch a cache line per light (most of a 1M-light frame's time).
  // Binned in parallel: each of `parts` runs of the lights counts its own per bucket, then puts
  // its lights after the earlier runs' of the same bucket.
  const int zFirst = box.lo[2] - dist, buckets = box.hi[2] - box.lo[2] + 2 * dist;
  const std::size_t parts = static_cast<std::size_t>(threadCount()), n = lights.size();
  const std::size_t nb = static_cast<std::size_t>(buckets);
  std::vector<std::size_t> count(parts * nb, 0), kept(parts, 0);
  std::vector<VoxelBox> reach(parts);  // per run: the voxels its lights reach (lo, hi inclusive)
  out.bucketOf.resize(n);
  parallelFor(parts, [&](std::size_t part) {
    VoxelBox& r = reach[part];
    r.lo = box.hi;
    for (std::size_t a = 0; a < 3; ++a) r.hi[a] = box.lo[a] - 1;
    for (std::size_t i = n * part / parts; i < n * (part + 1) / parts; ++i) {
      const LightParticle& l = lights[i];
      out.bucketOf[i] = -1;
      if (cull && !cull->keeps(l)) continue;
      ++kept[part];
      const int b = voxelOf(l.position[2], 2) - zFirst;
      std::array<int, 3> lo{}, hi{};
      if (b < 0 || b >= buckets || !within(l.position[0], 0, lo[0], hi[0]) ||
          !within(l.position[1], 1, lo[1], hi[1]) || !within(l.position[2], 2, lo[2], hi[2]))
        continue;  // no voxel of the box within its range
      for (std::size_t a = 0; a < 3; ++a)
        r.lo[a] = std::min(r.lo[a], lo[a]), r.hi[a] = std::max(r.hi[a], hi[a]);
      out.bucketOf[i] = b;
      ++count[part * nb + static_cast<std::size_t>(b)];
    }
  });
  // Where each run's lights of each bucket start in `sorted`: buckets in order, runs in order.
  std::vector<std::size_t> next(parts * nb), start(nb + 1, 0);
  std::size_t total = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    start[b] = total;
    for (std::size_t part = 0; part < parts; ++part)
      next[part * nb + b] = total, total += count[part * nb + b];
  }
  start[nb] = total;
  out.sorted.resize(total);
  parallelFor(parts, [&](std::size_t part) {
    std::size_t* at = next.data() + part * nb;
    for (std::size_t i = n * part / parts; i < n * (part + 1) / parts; ++i)
      if (const int b = out.bucketOf[i]; b >= 0)
        out.sorted[at[static_cast<std::size_t>(b)]++] = lights[i];
  });
  VoxelBox& t = out.touched;
  t.lo = box.hi, t.hi = box.lo;
  for (std::size_t part = 0; part < parts; ++part) {
    if (cull) out.lights += kept[part];
    for (std::size_t a = 0; a < 3; ++a)
      t.lo[a] = std::min(t.lo[a], reach[part].lo[a]),
      t.hi[a] = std::max(t.hi[a], reach[part].hi[a] + 1);
  }
  if (t.empty()) {
    t = VoxelBox{};
    return;
  }
  const int nx = t.hi[0] - t.lo[0], ny = t.hi[1] - t.lo[1], nz = t.hi[2] - t.lo[2];
  const std::size_t slice = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  // Every voxel of `touched` is written below: storage kept from the last frame needs no clear.
  out.colour.resize(slice * static_cast<std::size_t>(nz));
  out.direction.resize(out.colour.size());
  // Per thread, the sums of one slice of `touched`, all zero between slices. Made per call, not
  // kept: 48 bytes a voxel of a slice (200 MB a thread at 2048^2) would stay with the thread.
  std::vector<std::vector<std::array<std::int64_t, 6>>> sliceSums(
      static_cast<std::size_t>(threadCount()));
  // One z slice per task: it alone writes its voxels (STYLE.md rule 4), in a fixed order.
  parallelForDynamic(static_cast<std::size_t>(nz), 1, [&](std::size_t k) {
    const int z = t.lo[2] + static_cast<int>(k);
    std::vector<std::array<std::int64_t, 6>>& sums =
        sliceSums[static_cast<std::size_t>(threadIndex())];
    if (sums.size() < slice) sums.assign(slice, std::array<std::int64_t, 6>{});
    const int bLo = std::max(z - dist - zFirst, 0), bHi = std::min(z + dist - zFirst, buckets - 1);
    const float vz = d.origin.z() + (static_cast<float>(z) + 0.5f) * d.voxelSize;
    for (std::size_t s = start[static_cast<std::size_t>(bLo)];
         s < start[static_cast<std::size_t>(bHi) + 1]; ++s) {
      const LightParticle& l = out.sorted[s];
      if (std::abs(l.position[2] - vz) > d.range + 1e-3f * d.voxelSize) continue;  // as `within`
      int xLo = 0, xHi = 0, yLo = 0, yHi = 0;
      within(l.position[0], 0, xLo, xHi);
      within(l.position[1], 1, yLo, yHi);
      for (int y = yLo; y <= yHi; ++y) {
        const float vy = d.origin.y() + (static_cast<float>(y) + 0.5f) * d.voxelSize;
        for (int x = xLo; x <= xHi; ++x) {
          const float vx = d.origin.x() + (static_cast<float>(x) + 0.5f) * d.voxelSize;
          const float dx = l.position[0] - vx, dy = l.position[1] - vy, dz = l.position[2] - vz;
          const float r = std::sqrt(dx * dx + dy * dy + dz * dz);
          if (r > d.range) continue;
          const float att =
              1.0f / (d.attenuation[0] + d.attenuation[1] * r + d.attenuation[2] * r * r);
          // (p - voxel) / d * intensity, in the shader's order of operations.
          const float w = l.colour[3];
          const float terms[6] = {att * l.colour[0],         att * l.colour[1],
                                  att * l.colour[2],         r > 0 ? dx / r * w : 0.0f,
                                  r > 0 ? dy / r * w : 0.0f, r > 0 ? dz / r * w : 0.0f};
          std::array<std::int64_t, 6>& sum =
              sums[static_cast<std::size_t>(y - t.lo[1]) * static_cast<std::size_t>(nx) +
                   static_cast<std::size_t>(x - t.lo[0])];
          for (int c = 0; c < 6; ++c)
            sum[static_cast<std::size_t>(c)] += roundToInteger(terms[c] * scale);
        }
      }
    }
    // As lights_resolve.comp: the colour saturates at RGBA16F's 65504; a longer direction is
    // shortened whole (only its direction is used).
    constexpr float halfMax = 65504.0f;
    for (std::size_t i = 0; i < slice; ++i) {
      float c[3], v[3], longest = 0;
      for (std::size_t a = 0; a < 3; ++a) {
        c[a] = std::min(static_cast<float>(sums[i][a]) / scale, halfMax);
        v[a] = static_cast<float>(sums[i][a + 3]) / scale;
        longest = std::max(longest, std::abs(v[a]));
      }
      if (longest > halfMax)
        for (float& x : v) x *= halfMax / longest;
      out.colour[k * slice + i] = {toHalf(c[0]), toHalf(c[1]), toHalf(c[2]), 0};
      out.direction[k * slice + i] = {toHalf(v[0]), toHalf(v[1]), toHalf(v[2]), 0};
      sums[i] = {};
    }
  });
}

}  // namespace sph::render::lights
