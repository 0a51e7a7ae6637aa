#include "render/lights/CpuAccumulation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#ifdef __F16C__
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

VoxelSums accumulateOnCpu(const LightsDesc& d, const std::vector<LightParticle>& lights,
                          const VoxelBox& box, float scale) {
  VoxelSums out;
  if (box.empty()) return out;
  const int nx = box.hi[0] - box.lo[0], ny = box.hi[1] - box.lo[1], nz = box.hi[2] - box.lo[2];
  const std::size_t slice = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  out.colour.resize(slice * static_cast<std::size_t>(nz));
  out.direction.resize(out.colour.size());
  // The shader's loop: the voxel a light lies in and int(range / h) + 1 voxels either side.
  const int dist = static_cast<int>(d.range / d.voxelSize) + 1;
  auto voxelOf = [&](float x, int a) {
    return static_cast<int>(std::floor((x - d.origin[a]) / d.voxelSize));
  };
  // The lights by the z slice they lie in (those that reach the box's slices only), in their
  // given order: each slice then visits its 2 dist + 1 neighbouring buckets.
  const int zFirst = box.lo[2] - dist, buckets = nz + 2 * dist;
  std::vector<std::size_t> start(static_cast<std::size_t>(buckets) + 1, 0);
  std::vector<int> bucketOf(lights.size(), -1);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const int b = voxelOf(lights[i].position[2], 2) - zFirst;
    if (b < 0 || b >= buckets) continue;
    bucketOf[i] = b;
    ++start[static_cast<std::size_t>(b) + 1];
  }
  for (std::size_t b = 0; b < static_cast<std::size_t>(buckets); ++b) start[b + 1] += start[b];
  std::vector<std::uint32_t> sorted(start.back());
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < lights.size(); ++i)
      if (bucketOf[i] >= 0)
        sorted[next[static_cast<std::size_t>(bucketOf[i])]++] = static_cast<std::uint32_t>(i);
  }
  // The voxels along axis a whose centres lie within range of x (one or two of the shader's three
  // when range < h; a thousandth of a voxel more for rounding, the distance test decides), inside
  // the shader's loop and the box. The voxels the shader visits beyond are all out of range.
  auto within = [&](float x, int a, int& lo, int& hi) {
    const std::size_t s = static_cast<std::size_t>(a);
    const float g = (x - d.origin[a]) / d.voxelSize - 0.5f, r = d.range / d.voxelSize + 1e-3f;
    const int c = voxelOf(x, a);
    lo = std::max({static_cast<int>(std::ceil(g - r)), c - dist, box.lo[s]});
    hi = std::min({static_cast<int>(std::floor(g + r)), c + dist, box.hi[s] - 1});
  };
  // Per thread, the sums of one slice, all zero between slices: only the rows lights touched are
  // converted and zeroed again (most of a volume is dark; the output starts zero). Made per call,
  // not kept: 48 bytes a voxel of a slice (200 MB a thread at 2048^2) would stay with the thread.
  std::vector<std::vector<std::array<std::int64_t, 6>>> sliceSums(
      static_cast<std::size_t>(threadCount()));
  // One z slice per task: it alone writes its voxels (STYLE.md rule 4), in a fixed order.
  parallelForDynamic(static_cast<std::size_t>(nz), 1, [&](std::size_t k) {
    const int z = box.lo[2] + static_cast<int>(k);
    std::vector<std::array<std::int64_t, 6>>& sums =
        sliceSums[static_cast<std::size_t>(threadIndex())];
    if (sums.size() < slice) sums.assign(slice, std::array<std::int64_t, 6>{});
    int rowLo = box.hi[1], rowHi = box.lo[1] - 1;
    const int bLo = std::max(z - dist - zFirst, 0), bHi = std::min(z + dist - zFirst, buckets - 1);
    const float vz = d.origin.z() + (static_cast<float>(z) + 0.5f) * d.voxelSize;
    for (std::size_t s = start[static_cast<std::size_t>(bLo)];
         s < start[static_cast<std::size_t>(bHi) + 1]; ++s) {
      const LightParticle& l = lights[sorted[s]];
      if (std::abs(l.position[2] - vz) > d.range + 1e-3f * d.voxelSize) continue;  // as `within`
      int xLo = 0, xHi = 0, yLo = 0, yHi = 0;
      within(l.position[0], 0, xLo, xHi);
      within(l.position[1], 1, yLo, yHi);
      if (xLo <= xHi) rowLo = std::min(rowLo, yLo), rowHi = std::max(rowHi, yHi);
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
              sums[static_cast<std::size_t>(y - box.lo[1]) * static_cast<std::size_t>(nx) +
                   static_cast<std::size_t>(x - box.lo[0])];
          for (int t = 0; t < 6; ++t)
            sum[static_cast<std::size_t>(t)] += std::llrint(terms[t] * scale);
        }
      }
    }
    // As lights_resolve.comp: the colour saturates at RGBA16F's 65504; a longer direction is
    // shortened whole (only its direction is used).
    constexpr float halfMax = 65504.0f;
    const std::size_t first = static_cast<std::size_t>(std::max(rowLo - box.lo[1], 0)) * nx;
    const std::size_t last = static_cast<std::size_t>(std::max(rowHi + 1 - box.lo[1], 0)) * nx;
    for (std::size_t i = first; i < last; ++i) {
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
  return out;
}

}  // namespace sph::render::lights
