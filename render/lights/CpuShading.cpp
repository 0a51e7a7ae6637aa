#include "render/lights/CpuShading.h"

#include <algorithm>
#include <array>
#include <cmath>
#if defined(__F16C__)
#include <immintrin.h>
#endif

#include "render/splat/Srgb8Table.h"
#include "sim/Parallel.h"

namespace sph::render::lights {
namespace {

using Texel = std::array<std::uint16_t, 4>;

// out += w * t (four halves at once where the CPU converts them).
inline void addWeighted(const Texel& t, float w, float out[4]) {
#if defined(__F16C__)
  const __m128 v = _mm_cvtph_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(t.data())));
  _mm_storeu_ps(out, _mm_add_ps(_mm_loadu_ps(out), _mm_mul_ps(_mm_set1_ps(w), v)));
#else
  for (std::size_t c = 0; c < 4; ++c) out[c] += w * fromHalf(t[c]);
#endif
}

}  // namespace

CpuShading::CpuShading(const LightsDesc& desc, const VoxelSums& sums, int terms)
    : desc_(desc),
      sums_(sums),
      terms_(terms),
      wholeShininess_(
          desc.shininess == std::floor(desc.shininess) ? static_cast<int>(desc.shininess) : 0) {}

void CpuShading::filtered(const float g[3], float colour[4], float direction[4]) const {
  std::fill(colour, colour + 4, 0.0f), std::fill(direction, direction + 4, 0.0f);
  const VoxelBox& t = sums_.touched;
  if (t.empty()) return;
  const int nx = t.hi[0] - t.lo[0], ny = t.hi[1] - t.lo[1];
  auto at = [&](int x, int y, int z) {
    return (static_cast<std::size_t>(z - t.lo[2]) * static_cast<std::size_t>(ny) +
            static_cast<std::size_t>(y - t.lo[1])) *
               static_cast<std::size_t>(nx) +
           static_cast<std::size_t>(x - t.lo[0]);
  };
  auto inside = [&](int x, int y, int z) {
    return x >= t.lo[0] && x < t.hi[0] && y >= t.lo[1] && y < t.hi[1] && z >= t.lo[2] &&
           z < t.hi[2];
  };
  if (desc_.filter == LightFilter::Nearest) {  // lightTexel(floor(g)): zero outside
    const int x = static_cast<int>(std::floor(g[0])), y = static_cast<int>(std::floor(g[1])),
              z = static_cast<int>(std::floor(g[2]));
    if (!inside(x, y, z)) return;
    addWeighted(sums_.colour[at(x, y, z)], 1.0f, colour);
    addWeighted(sums_.direction[at(x, y, z)], 1.0f, direction);
    return;
  }
  // GL's linear filter with a zero border: the 2 x 2 x 2 voxel centres around g, weights from
  // the fraction past the lower centre, in float as llvmpipe has them for float textures (its
  // results agree to 1e-3, tests/test_lights_shade.cpp; 8-bit weights would not). Voxels outside
  // `touched` (and the volume) read zero.
  int i[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    const float c = g[a] - 0.5f, fl = std::floor(c);
    i[a] = static_cast<int>(fl), f[a] = c - fl;
  }
  if (i[0] + 1 < t.lo[0] || i[0] >= t.hi[0] || i[1] + 1 < t.lo[1] || i[1] >= t.hi[1] ||
      i[2] + 1 < t.lo[2] || i[2] >= t.hi[2])
    return;  // all eight outside: most of a frame's pixels where the lights fill a corner
  const bool whole = inside(i[0], i[1], i[2]) && inside(i[0] + 1, i[1] + 1, i[2] + 1);
  for (int dz = 0; dz < 2; ++dz) {
    const float wz = dz ? f[2] : 1.0f - f[2];
    for (int dy = 0; dy < 2; ++dy) {
      const float wyz = wz * (dy ? f[1] : 1.0f - f[1]);
      for (int dx = 0; dx < 2; ++dx) {
        const int x = i[0] + dx, y = i[1] + dy, z = i[2] + dz;
        if (!whole && !inside(x, y, z)) continue;
        const float w = wyz * (dx ? f[0] : 1.0f - f[0]);
        const std::size_t k = at(x, y, z);
        addWeighted(sums_.colour[k], w, colour);
        addWeighted(sums_.direction[k], w, direction);
      }
    }
  }
}

void CpuShading::sample(const float g[3], float colour[4], float direction[4]) const {
  const int n = desc_.oversampling;
  if (n <= 1) return filtered(g, colour, direction);
  // extra_lights.glsl's lightSampled: the mean of n^3 samples spread over one voxel around g.
  std::fill(colour, colour + 4, 0.0f), std::fill(direction, direction + 4, 0.0f);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int k[3] = {x, y, z};
        float s[3], c[4], d[4];
        for (int a = 0; a < 3; ++a)
          s[a] = g[a] + (static_cast<float>(k[a]) + 0.5f) / static_cast<float>(n) - 0.5f;
        filtered(s, c, d);
        for (int a = 0; a < 4; ++a) colour[a] += c[a], direction[a] += d[a];
      }
  const float inv = 1.0f / static_cast<float>(n * n * n);
  for (int a = 0; a < 4; ++a) colour[a] *= inv, direction[a] *= inv;
}

Vec3 CpuShading::at(const Vec3& position, const Vec3& n, const Vec3& toEye,
                    const Vec3& base) const {
  return term(position, n, &toEye, Vec3::Zero(), base);
}

Vec3 CpuShading::term(const Vec3& position, const Vec3& n, const Vec3* toEye, const Vec3& eye,
                      const Vec3& base) const {
  float g[3], colour[4], direction[4];
  for (int a = 0; a < 3; ++a) g[a] = (position[a] - desc_.origin[a]) / desc_.voxelSize;
  sample(g, colour, direction);
  const float len = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                              direction[2] * direction[2]);
  if (len < 1e-6f) return Vec3::Zero();  // most pixels where the lights fill a corner
  const Vec3 l(direction[0] / len, direction[1] / len, direction[2] / len);
  const Vec3 c(std::max(colour[0], 0.0f), std::max(colour[1], 0.0f), std::max(colour[2], 0.0f));
  Vec3 out = Vec3::Zero();
  const float nl = n.dot(l);
  if (terms_ & 1) out += desc_.diffuse * base.cwiseProduct(c) * std::max(nl, 0.0f);
  if (terms_ & 2) {
    const Vec3 r = 2.0f * nl * n - l;  // reflect(-l, n)
    const float re = std::max(r.dot(toEye ? *toEye : (eye - position).normalized()), 0.0f);
    out += desc_.specular * c * power(re);
  }
  return out;
}

float CpuShading::power(float x) const {
  if (wholeShininess_ == 0) return std::pow(x, desc_.shininess);
  // A whole exponent (the default 16) by squaring: 4 multiplies instead of a libm call; the
  // same to float rounding.
  float result = 1.0f, b = x;
  for (int e = wholeShininess_; e > 0; e >>= 1, b *= b)
    if (e & 1) result *= b;
  return result;
}

void CpuShading::pixels(const splat::GBufferPixels& g, const Vec3& eye, std::uint8_t* rgba) const {
  const splat::Srgb8Table& encode = splat::srgb8Table();
  const std::array<double, 16>& m = g.fromNdc;
  parallelForDynamic(static_cast<std::size_t>(g.height), 1, [&](std::size_t row) {
    const double ndcY = 2.0 * (static_cast<double>(row) + 0.5) / g.height - 1.0;
    for (std::size_t col = 0; col < static_cast<std::size_t>(g.width); ++col) {
      const std::size_t i = row * static_cast<std::size_t>(g.width) + col;
      std::uint8_t* out = rgba + 4 * i;
      const float depth = g.depth[i];
      if (depth >= 1.0f) {  // nothing drawn here (the depth is cleared to 1 each frame)
        out[0] = out[1] = out[2] = out[3] = 0;
        continue;
      }
      Vec3 at3;
      if (g.position) {
        at3 = Vec3(g.position[4 * i], g.position[4 * i + 1], g.position[4 * i + 2]);
      } else {
        // The pixel's centre back through the frame's matrices: NDC -> world, in double (depth
        // near 1 holds the distance in its last bits).
        const double ndc[3] = {2.0 * (static_cast<double>(col) + 0.5) / g.width - 1.0, ndcY,
                               2.0 * static_cast<double>(depth) - 1.0};
        double p[4];
        for (std::size_t r = 0; r < 4; ++r)
          p[r] = m[r] * ndc[0] + m[4 + r] * ndc[1] + m[8 + r] * ndc[2] + m[12 + r];
        at3 = Vec3(static_cast<float>(p[0] / p[3]), static_cast<float>(p[1] / p[3]),
                   static_cast<float>(p[2] / p[3]));
      }
      const float* nn = g.normal + 4 * i;
      const std::uint16_t* b = g.albedo + 4 * i;
      const Vec3 base(fromHalf(b[0]), fromHalf(b[1]), fromHalf(b[2]));
      const Vec3 c = term(at3, Vec3(nn[0], nn[1], nn[2]), nullptr, eye, base);
      const float* lit = g.lit + 4 * i;
      for (int k = 0; k < 3; ++k) out[k] = encode(lit[k] + c[k]);
      out[3] = 255;
    }
  });
}

}  // namespace sph::render::lights
