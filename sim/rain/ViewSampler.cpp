#include "sim/rain/ViewSampler.h"

#if defined(__AVX512F__) && defined(__AVX512DQ__)
#include <immintrin.h>
// GCC 12 warns of the `_mm512_undefined_*()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace sph::rain {

#if defined(__AVX512F__) && defined(__AVX512DQ__)
namespace {

// mix64 (RainRandom.h) of 8 lanes.
__m512i mix64Lanes(__m512i z) {
  z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)),
                         _mm512_set1_epi64(static_cast<long long>(0xbf58476d1ce4e5b9ULL)));
  z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)),
                         _mm512_set1_epi64(static_cast<long long>(0x94d049bb133111ebULL)));
  return _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
}

// cubeCoordinate of the 21 bits at `shift` of the 16 hashes lo (candidates 0-7) and hi (8-15).
__m512 coordinateLanes(__m512i lo, __m512i hi, unsigned shift) {
  const __m512i bits = _mm512_set1_epi64(0x1fffff);
  const __m256i a = _mm512_cvtepi64_epi32(_mm512_and_si512(_mm512_srli_epi64(lo, shift), bits));
  const __m256i b = _mm512_cvtepi64_epi32(_mm512_and_si512(_mm512_srli_epi64(hi, shift), bits));
  const __m512i both = _mm512_inserti64x4(_mm512_castsi256_si512(a), b, 1);
  const __m512i odd = _mm512_sub_epi32(_mm512_slli_epi32(both, 1), _mm512_set1_epi32(0x1fffff));
  return _mm512_mul_ps(_mm512_cvtepi32_ps(odd), _mm512_set1_ps(1.0f / 2097152.0f));
}

// RainSpace::along in lanes: the same fused multiply-adds in the same order.
__m512 alongLanes(__m512 x, __m512 y, __m512 z, const Vec3& o, const Vec3& n) {
  const __m512 dx = _mm512_sub_ps(x, _mm512_set1_ps(o.x()));
  const __m512 dy = _mm512_sub_ps(y, _mm512_set1_ps(o.y()));
  const __m512 dz = _mm512_sub_ps(z, _mm512_set1_ps(o.z()));
  return _mm512_fmadd_ps(
      dx, _mm512_set1_ps(n.x()),
      _mm512_fmadd_ps(dy, _mm512_set1_ps(n.y()), _mm512_mul_ps(dz, _mm512_set1_ps(n.z()))));
}

}  // namespace

void viewCandidates16(const RainSpace& s, const DropRandom& u, std::uint64_t first,
                      ViewCandidates16& out) {
  const __m512i key = _mm512_set1_epi64(static_cast<long long>(u.key()));
  const __m512i base = _mm512_set1_epi64(static_cast<long long>(u.offset() + first));
  const __m512i lo = mix64Lanes(
      _mm512_xor_si512(key, _mm512_add_epi64(base, _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7))));
  const __m512i hi = mix64Lanes(_mm512_xor_si512(
      key, _mm512_add_epi64(base, _mm512_setr_epi64(8, 9, 10, 11, 12, 13, 14, 15))));
  const __m512 r = _mm512_set1_ps(s.radius);
  const __m512 x = _mm512_fmadd_ps(r, coordinateLanes(lo, hi, 0), _mm512_set1_ps(s.centre.x()));
  const __m512 y = _mm512_fmadd_ps(r, coordinateLanes(lo, hi, 21), _mm512_set1_ps(s.centre.y()));
  const __m512 z = _mm512_fmadd_ps(r, coordinateLanes(lo, hi, 42), _mm512_set1_ps(s.centre.z()));
  // insideSphere: along(p, centre, p - centre) <= radius^2
  const __m512 dx = _mm512_sub_ps(x, _mm512_set1_ps(s.centre.x()));
  const __m512 dy = _mm512_sub_ps(y, _mm512_set1_ps(s.centre.y()));
  const __m512 dz = _mm512_sub_ps(z, _mm512_set1_ps(s.centre.z()));
  const __m512 d2 = _mm512_fmadd_ps(dx, dx, _mm512_fmadd_ps(dy, dy, _mm512_mul_ps(dz, dz)));
  const __mmask16 sphere = _mm512_cmp_ps_mask(d2, _mm512_set1_ps(s.radius * s.radius), _CMP_LE_OQ);
  // insideSides, eq. (8)-(9)
  const __m512 zero = _mm512_setzero_ps();
  __mmask16 inside = sphere;
  inside &= _mm512_cmp_ps_mask(alongLanes(x, y, z, s.ntr, s.R), zero, _CMP_GE_OQ);
  inside &= _mm512_cmp_ps_mask(alongLanes(x, y, z, s.nbl, s.L), zero, _CMP_GE_OQ);
  inside &= _mm512_cmp_ps_mask(alongLanes(x, y, z, s.ntr, s.T), zero, _CMP_GE_OQ);
  inside &= _mm512_cmp_ps_mask(alongLanes(x, y, z, s.nbl, s.B), zero, _CMP_GE_OQ);
  _mm512_storeu_ps(out.x, x), _mm512_storeu_ps(out.y, y), _mm512_storeu_ps(out.z, z);
  out.inSphere = sphere, out.inside = inside;
}

#else

void viewCandidates16(const RainSpace& s, const DropRandom& u, std::uint64_t first,
                      ViewCandidates16& out) {
  out.inSphere = out.inside = 0;
  for (unsigned k = 0; k < 16; ++k) {
    const ViewCandidate c = viewCandidate(s, u.bits(first + k));
    out.x[k] = c.p.x(), out.y[k] = c.p.y(), out.z[k] = c.p.z();
    out.inSphere |= static_cast<std::uint32_t>(c.inSphere) << k;
    out.inside |= static_cast<std::uint32_t>(c.inside) << k;
  }
}

#endif

}  // namespace sph::rain
