#include "render/rain/ComposeOver.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VL__)
// GCC 12 warns of the `_mm512_undefined_*()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#define SPH_COMPOSE_LANES 1
#endif

#include "sim/Assert.h"

namespace sph::render::rain {
namespace {

// Pixels [first, end), one at a time.
void composePixels(const float* layer, std::uint8_t* rgba, std::ptrdiff_t first,
                   std::ptrdiff_t end) {
  for (std::ptrdiff_t p = first; p < end; ++p) {
    const float* l = layer + 4 * p;
    std::uint8_t* c = rgba + 4 * p;
    for (int k = 0; k < 3; ++k) {
#if defined(SPH_COMPOSE_LANES)
      const float v = std::fma(l[3], static_cast<float>(c[k]), 255 * l[k]);  // as the lanes
#else
      const float v = l[3] * static_cast<float>(c[k]) + 255 * l[k];
#endif
      c[k] = static_cast<std::uint8_t>(std::min(255.0f, std::max(0.0f, v)) + 0.5f);
    }
  }
}

}  // namespace

void composeOver(const std::vector<float>& layer, std::vector<std::uint8_t>& rgba) {
  SPH_ASSERT(layer.size() == rgba.size());
  const auto pixels = static_cast<std::ptrdiff_t>(rgba.size() / 4);
#if defined(SPH_COMPOSE_LANES)
  // 4 pixels a vector (16 floats of the layer, 16 bytes of the frame); GCC left the loop above
  // scalar (a tenth of the frame's time after the resolve:
  // docs/notes/2026-11-27-rain-respawn-and-sums.md, "The resolve's exp and the composite in
  // AVX-512 lanes").
  const std::ptrdiff_t blocks = pixels / 4;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    const __m512 l = _mm512_loadu_ps(layer.data() + 16 * b);
    std::uint8_t* c = rgba.data() + 16 * b;
    const __m512 frame =
        _mm512_cvtepi32_ps(_mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<__m128i*>(c))));
    const __m512 t = _mm512_shuffle_ps(l, l, _MM_SHUFFLE(3, 3, 3, 3));
    __m512 v = _mm512_fmadd_ps(t, frame, _mm512_mul_ps(_mm512_set1_ps(255.0f), l));
    v = _mm512_min_ps(_mm512_set1_ps(255.0f), _mm512_max_ps(_mm512_setzero_ps(), v));
    const __m512i bytes = _mm512_cvttps_epi32(_mm512_add_ps(v, _mm512_set1_ps(0.5f)));
    // The red, green and blue bytes; each pixel's alpha as it was.
    _mm_mask_storeu_epi8(c, 0x7777, _mm512_cvtepi32_epi8(bytes));
  }
  composePixels(layer.data(), rgba.data(), 4 * blocks, pixels);
#else
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t p = 0; p < pixels; ++p) composePixels(layer.data(), rgba.data(), p, p + 1);
#endif
}

}  // namespace sph::render::rain
