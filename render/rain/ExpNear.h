// exp(x) for the sums' resolve (render/rain/StreakSums.cpp), T = exp(-sum b) a pixel, in 16
// AVX-512 lanes and one at a time with the same operations, so both give the same bits: std::expf,
// a call per pixel the lanes cannot take, was a fifth of the resolve. x = n ln 2 + r with |r| <=
// ln 2 / 2; exp(r) by its Taylor polynomial to r^7 (truncation under 5e-9, below the float's 6e-8),
// times 2^n exactly: within 1 ulp of std::exp, with FMA or without (measured; the test allows 2).
// x is taken at no less than -87 (exp -87 = 1.6e-38, near the least normal float) rather than
// going to 0: a T that small scales an 8-bit colour to 0 all the same.
#pragma once

#include <algorithm>
#include <cmath>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace sph::render::rain {

namespace exp_near {
constexpr float kMinExponent = -87.0f, kLog2e = 1.44269504f;
// ln 2 in two parts, the first with 15 significant bits, so n kLn2Hi is exact for |n| <= 126.
constexpr float kLn2Hi = 0.693145752f, kLn2Lo = 1.42860677e-6f;
constexpr float kTaylor[8] = {1.0f,         1.0f,          0.5f,          1.0f / 6.0f,
                              1.0f / 24.0f, 1.0f / 120.0f, 1.0f / 720.0f, 1.0f / 5040.0f};

// a b + c in one rounding where the CPU has FMA (every AVX-512 one, so the lanes' bits); without
// it std::fma is a library call, 5x the resolve's time, and two roundings do.
inline float multiplyAdd(float a, float b, float c) {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}
}  // namespace exp_near

inline float expNear(float x) {
  using namespace exp_near;
  x = std::max(x, kMinExponent);
  const float n = std::nearbyint(x * kLog2e);
  const float r = multiplyAdd(n, -kLn2Lo, multiplyAdd(n, -kLn2Hi, x));
  float p = kTaylor[7];
  for (int i = 6; i >= 0; --i) p = multiplyAdd(p, r, kTaylor[i]);
  return std::ldexp(p, static_cast<int>(n));
}

#if defined(__AVX512F__)
inline __m512 expNear(__m512 x) {
  using namespace exp_near;
  x = _mm512_max_ps(x, _mm512_set1_ps(kMinExponent));
  const __m512 n = _mm512_roundscale_ps(_mm512_mul_ps(x, _mm512_set1_ps(kLog2e)),
                                        _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  const __m512 r =
      _mm512_fmadd_ps(n, _mm512_set1_ps(-kLn2Lo), _mm512_fmadd_ps(n, _mm512_set1_ps(-kLn2Hi), x));
  __m512 p = _mm512_set1_ps(kTaylor[7]);
  for (int i = 6; i >= 0; --i) p = _mm512_fmadd_ps(p, r, _mm512_set1_ps(kTaylor[i]));
  return _mm512_scalef_ps(p, n);
}
#endif

}  // namespace sph::render::rain
