#include "render/lights/CpuAccumulation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#if defined(__F16C__) || defined(__x86_64__)
#include <immintrin.h>
#endif
// AVX-512 (F, DQ): the count pass tests 16 lights at a time (testSixteen).
#if defined(__AVX512F__) && defined(__AVX512DQ__)
#define SPHSPLAT_SUMS_AVX512 1
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

float fromHalf(std::uint16_t h) {
#ifdef __F16C__
  return _cvtsh_ss(h);
#else
  const int exponent = (h >> 10) & 0x1f, mantissa = h & 0x3ff;
  float v = 0;
  if (exponent == 0)
    v = std::ldexp(static_cast<float>(mantissa), -24);  // zero or subnormal
  else if (exponent == 31)
    v = mantissa ? NAN : INFINITY;
  else
    v = std::ldexp(static_cast<float>(mantissa | 0x400), exponent - 25);
  return (h & 0x8000) ? -v : v;
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

#ifdef SPHSPLAT_SUMS_AVX512
// GCC 12 warns of the `_mm512_undefined_*()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593): off for this function only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
// The count pass's test of 16 lights at once (lights[0..16)): which the cull keeps, and the
// voxels each reaches along each axis (`lo`, `hi`, inclusive) - accumulateOnCpu's keeps() and
// within() with the same steps in the same order, lane by lane: ViewCull::keeps as GCC builds
// it (the plane's dot product y, z, x with two fused multiply-adds, then + w; the squared
// distance to the box z, y, x, the last two fused), the voxel ranges in plain IEEE steps.
// `inside`: the lanes kept that reach a voxel of the box.
struct Sixteen {
  alignas(64) std::int32_t lo[3][16], hi[3][16];
  __mmask16 kept = 0, inside = 0;
};
inline void testSixteen(const sph::lights::LightParticle* lights, const ViewCull* cull,
                        const scene::LightsDesc& d, const VoxelBox& box, int dist, float r,
                        Sixteen& out) {
  const __m512i stride = _mm512_mullo_epi32(
      _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
      _mm512_set1_epi32(static_cast<int>(sizeof(sph::lights::LightParticle) / sizeof(float))));
  __m512 p[3];
  for (int a = 0; a < 3; ++a) p[a] = _mm512_i32gather_ps(stride, lights[0].position.data() + a, 4);
  __mmask16 keep = 0xffff;
  if (cull && cull->empty()) keep = 0;
  if (cull && !cull->empty()) {
    const __m512 below = _mm512_set1_ps(-cull->reach());
    for (const Eigen::Vector4f& q : cull->frustum().planes) {
      __m512 t = _mm512_mul_ps(_mm512_set1_ps(q.y()), p[1]);
      t = _mm512_fmadd_ps(_mm512_set1_ps(q.z()), p[2], t);
      t = _mm512_fmadd_ps(_mm512_set1_ps(q.x()), p[0], t);
      t = _mm512_add_ps(t, _mm512_set1_ps(q.w()));
      keep &= static_cast<__mmask16>(~_mm512_cmp_ps_mask(below, t, _CMP_GT_OQ));
    }
    __m512 e[3];
    for (int a = 0; a < 3; ++a)
      e[a] = _mm512_sub_ps(_mm512_min_ps(_mm512_set1_ps(cull->hi()[a]),
                                         _mm512_max_ps(_mm512_set1_ps(cull->lo()[a]), p[a])),
                           p[a]);
    __m512 squared = _mm512_mul_ps(e[2], e[2]);
    squared = _mm512_fmadd_ps(e[1], e[1], squared);
    squared = _mm512_fmadd_ps(e[0], e[0], squared);
    const float range2 = cull->range() * cull->range();
    keep &= _mm512_cmp_ps_mask(_mm512_set1_ps(range2), squared, _CMP_GE_OQ);
  }
  __mmask16 inside = keep;
  for (int a = 0; a < 3; ++a) {
    const __m512 cell = _mm512_div_ps(_mm512_sub_ps(p[a], _mm512_set1_ps(d.origin[a])),
                                      _mm512_set1_ps(d.voxelSize));
    const __m512 g = _mm512_sub_ps(cell, _mm512_set1_ps(0.5f));
    const __m512i c =
        _mm512_cvttps_epi32(_mm512_roundscale_ps(cell, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
    const __m512i lo = _mm512_max_epi32(
        _mm512_max_epi32(
            _mm512_cvttps_epi32(_mm512_roundscale_ps(_mm512_sub_ps(g, _mm512_set1_ps(r)),
                                                     _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC)),
            _mm512_sub_epi32(c, _mm512_set1_epi32(dist))),
        _mm512_set1_epi32(box.lo[static_cast<std::size_t>(a)]));
    const __m512i hi = _mm512_min_epi32(
        _mm512_min_epi32(
            _mm512_cvttps_epi32(_mm512_roundscale_ps(_mm512_add_ps(g, _mm512_set1_ps(r)),
                                                     _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)),
            _mm512_add_epi32(c, _mm512_set1_epi32(dist))),
        _mm512_set1_epi32(box.hi[static_cast<std::size_t>(a)] - 1));
    inside &= _mm512_cmple_epi32_mask(lo, hi);
    _mm512_store_si512(out.lo[a], lo), _mm512_store_si512(out.hi[a], hi);
  }
  out.kept = keep, out.inside = inside;
}
#pragma GCC diagnostic pop
#endif

}  // namespace

void accumulateOnCpu(const scene::LightsDesc& d,
                     const std::vector<sph::lights::LightParticle>& lights, const VoxelBox& box,
                     float scale, const ViewCull* cull, VoxelSums& out) {
  out.touched = VoxelBox{};
  out.lights = cull ? 0 : lights.size();
  if (box.empty()) return;
  // The shader's loop: the voxel a light lies in and int(range / h) + 1 voxels either side.
  const int dist = static_cast<int>(d.range / d.voxelSize) + 1;
  const float r = d.range / d.voxelSize + 1e-3f;
  // The voxels along axis a whose centres lie within range of x (one or two of the shader's three
  // when range < h; a thousandth of a voxel more for rounding, the distance test decides), inside
  // the shader's loop and the box. The voxels the shader visits beyond are all out of range.
  auto within = [&](float x, std::size_t a, int& lo, int& hi) {
    const float cell = (x - d.origin[static_cast<int>(a)]) / d.voxelSize, g = cell - 0.5f;
    const int c = static_cast<int>(std::floor(cell));
    lo = std::max({static_cast<int>(std::ceil(g - r)), c - dist, box.lo[a]});
    hi = std::min({static_cast<int>(std::floor(g + r)), c + dist, box.hi[a] - 1});
    return lo <= hi;
  };
  // Each light the cull keeps, with the voxels it reaches along x and y, in the list of every z
  // slice of the box it reaches (one, rarely two at Fig. 11's range), in the lights' given order:
  // a slice then reads exactly its lights, in a row. Binned in parallel: each of `parts` runs of
  // the lights counts its own per slice, then puts them after the earlier runs' of that slice.
  const std::size_t parts = static_cast<std::size_t>(threadCount()), n = lights.size();
  const std::size_t slices = static_cast<std::size_t>(box.hi[2] - box.lo[2]);
  std::vector<std::size_t> count(parts * slices, 0), kept(parts, 0);
  std::vector<VoxelBox> reach(parts);  // per run: the voxels its lights reach (lo, hi inclusive)
  for (std::size_t a = 0; a < 3; ++a)
    if (box.hi[a] - box.lo[a] > 65536)  // the 16-bit voxels of Reach and BinnedLight
      throw std::length_error("accumulateOnCpu: a box of more than 65536 voxels a side");
  out.reachOf.resize(n);
  parallelFor(parts, [&](std::size_t part) {
    // Locals, not the captured references: the counts' stores (size_t) may alias those, so the
    // compiler loaded them and recomputed the run's bounds for every light (perf annotate).
    VoxelBox rp;
    rp.lo = box.hi;
    for (std::size_t a = 0; a < 3; ++a) rp.hi[a] = box.lo[a] - 1;
    std::size_t keptHere = 0;
    std::size_t* const counts = count.data() + part * slices;
    VoxelSums::Reach* const reachOf = out.reachOf.data();
    const std::size_t first = n * part / parts, last = n * (part + 1) / parts;
    const int zFirst = box.lo[2];
    std::size_t i = first;
#ifdef SPHSPLAT_SUMS_AVX512
    for (; i + 16 <= last; i += 16) {  // the rest, fewer than 16, as below
      Sixteen t;
      testSixteen(&lights[i], cull, d, box, dist, r, t);
      keptHere += static_cast<std::size_t>(__builtin_popcount(t.kept));
      for (std::size_t j = 0; j < 16; ++j) {
        VoxelSums::Reach& v = reachOf[i + j];
        if (!((t.inside >> j) & 1u)) {
          v.lo[2] = 1, v.hi[2] = 0;
          continue;
        }
        for (std::size_t a = 0; a < 3; ++a) {
          const int lo = t.lo[a][j], hi = t.hi[a][j];
          v.lo[a] = static_cast<std::uint16_t>(lo - box.lo[a]);
          v.hi[a] = static_cast<std::uint16_t>(hi - box.lo[a]);
          rp.lo[a] = std::min(rp.lo[a], lo), rp.hi[a] = std::max(rp.hi[a], hi);
        }
        for (int z = t.lo[2][j]; z <= t.hi[2][j]; ++z)
          ++counts[static_cast<std::size_t>(z - zFirst)];
      }
    }
#endif
    for (; i < last; ++i) {
      const sph::lights::LightParticle& l = lights[i];
      VoxelSums::Reach& v = reachOf[i];  // left empty for a light that adds nothing
      v.lo[2] = 1, v.hi[2] = 0;
      if (cull && !cull->keeps(l)) continue;
      ++keptHere;
      std::array<int, 3> lo{}, hi{};
      if (!within(l.position[0], 0, lo[0], hi[0]) || !within(l.position[1], 1, lo[1], hi[1]) ||
          !within(l.position[2], 2, lo[2], hi[2]))
        continue;  // no voxel of the box within its range
      for (std::size_t a = 0; a < 3; ++a) {
        v.lo[a] = static_cast<std::uint16_t>(lo[a] - box.lo[a]);
        v.hi[a] = static_cast<std::uint16_t>(hi[a] - box.lo[a]);
        rp.lo[a] = std::min(rp.lo[a], lo[a]), rp.hi[a] = std::max(rp.hi[a], hi[a]);
      }
      for (int z = lo[2]; z <= hi[2]; ++z) ++counts[static_cast<std::size_t>(z - zFirst)];
    }
    reach[part] = rp, kept[part] = keptHere;
  });
  // Where each run's lights of each slice start in `binned`: slices in order, runs in order.
  std::vector<std::size_t> next(parts * slices), start(slices + 1, 0);
  std::size_t total = 0;
  for (std::size_t z = 0; z < slices; ++z) {
    start[z] = total;
    for (std::size_t part = 0; part < parts; ++part)
      next[part * slices + z] = total, total += count[part * slices + z];
  }
  start[slices] = total;
  out.binned.resize(total);
  parallelFor(parts, [&](std::size_t part) {
    std::size_t* const at = next.data() + part * slices;  // locals, as above
    const VoxelSums::Reach* const reachOf = out.reachOf.data();
    VoxelSums::BinnedLight* const binned = out.binned.data();
    const std::size_t first = n * part / parts, last = n * (part + 1) / parts;
    for (std::size_t i = first; i < last; ++i) {
      const VoxelSums::Reach& v = reachOf[i];
      if (v.lo[2] > v.hi[2]) continue;  // culled or out of the box: its light is not read
      const sph::lights::LightParticle& l = lights[i];
      const VoxelSums::BinnedLight b{{l.position[0], l.position[1], l.position[2]},
                                     l.colour,
                                     {v.lo[0], v.hi[0], v.lo[1], v.hi[1]}};
      for (std::size_t z = v.lo[2]; z <= v.hi[2]; ++z) binned[at[z]++] = b;
    }
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
    const float vz = d.origin.z() + (static_cast<float>(z) + 0.5f) * d.voxelSize;
    const std::size_t list = static_cast<std::size_t>(z - box.lo[2]);
    for (std::size_t s = start[list]; s < start[list + 1]; ++s) {
      const VoxelSums::BinnedLight& l = out.binned[s];
      for (int y = box.lo[1] + l.xy[2]; y <= box.lo[1] + l.xy[3]; ++y) {
        const float vy = d.origin.y() + (static_cast<float>(y) + 0.5f) * d.voxelSize;
        for (int x = box.lo[0] + l.xy[0]; x <= box.lo[0] + l.xy[1]; ++x) {
          const float vx = d.origin.x() + (static_cast<float>(x) + 0.5f) * d.voxelSize;
          const float dx = l.position[0] - vx, dy = l.position[1] - vy, dz = l.position[2] - vz;
          const float dr = std::sqrt(dx * dx + dy * dy + dz * dz);
          if (dr > d.range) continue;
          const float att =
              1.0f / (d.attenuation[0] + d.attenuation[1] * dr + d.attenuation[2] * dr * dr);
          // (p - voxel) / d * intensity, in the shader's order of operations.
          const float w = l.colour[3];
          const float terms[6] = {att * l.colour[0],           att * l.colour[1],
                                  att * l.colour[2],           dr > 0 ? dx / dr * w : 0.0f,
                                  dr > 0 ? dy / dr * w : 0.0f, dr > 0 ? dz / dr * w : 0.0f};
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
      const std::array<std::int64_t, 6>& s = sums[i];
      if ((s[0] | s[1] | s[2] | s[3] | s[4] | s[5]) == 0) {  // no light here: zero, as below
        out.colour[k * slice + i] = out.direction[k * slice + i] = {0, 0, 0, 0};
        continue;
      }
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
