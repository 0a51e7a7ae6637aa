#include "render/lights/CpuShading.h"

#include <algorithm>
#include <array>
#include <cmath>
#if defined(__F16C__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "render/frame/Srgb8Table.h"
#include "sim/Parallel.h"

namespace sph::render::lights {

// Up to kRun pixels of one row: the columns of a block of the row, then its lit pixels packed
// (what phong() reads and writes). On the stack (~26 KB): at() uses one of one pixel, pixels()
// one a row.
struct CpuShading::Run {
  static constexpr std::size_t kRun = 256;
  // The block's voxel coordinates, fractions past the lower voxel centre and vectors to the eye
  // (by column); the lit pixels' normal, base colour, sampled colour and direction, and
  // reflection cosine (packed).
  // clang-format off
  enum Field { Gx, Gy, Gz, Fx, Fy, Fz, Ex, Ey, Ez, Nx, Ny, Nz, Br, Bg, Bb, Cr, Cg, Cb, Dx, Dy, Dz,
               Re, kFields };
  // clang-format on
  alignas(64) float f[kFields][kRun];
  std::array<std::uint16_t, kRun> column;  // a packed pixel's column in the block
  alignas(64) int lower[3][kRun];  // a column's lower voxel centre (Fx..: the fraction past it)
};

namespace {

using Texel = std::array<std::uint16_t, 4>;
using Run = CpuShading::Run;

// fromHalf, inlined where the CPU converts halves.
inline float halfToFloat(std::uint16_t h) {
#if defined(__F16C__)
  return _cvtsh_ss(h);
#else
  return fromHalf(h);
#endif
}

// The unit vector from p to the eye: the same operations in pixels()'s lanes and in toEye().
inline void unitTo(float ex, float ey, float ez, float px, float py, float pz, float& ux, float& uy,
                   float& uz) {
  const float dx = ex - px, dy = ey - py, dz = ez - pz;
  const float inv = 1.0f / std::sqrt(dx * dx + dy * dy + dz * dz);  // one division, not three
  ux = dx * inv, uy = dy * inv, uz = dz * inv;
}

// The lower of the two voxel centres around voxel coordinate g along one axis, and g's fraction
// past it (the filter's weight of the upper one).
inline void lowerCentre(float g, int& i, float& f) {
  const float c = g - 0.5f, fl = std::floor(c);
  i = static_cast<int>(fl), f = c - fl;
}

// lowerCentre over n voxel coordinates along one axis, in SIMD lanes.
void lowerCentres(const float* __restrict g, int* __restrict lower, float* __restrict fraction,
                  int n) {
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    const float c = g[k] - 0.5f, fl = std::floor(c);
    lower[k] = static_cast<int>(fl), fraction[k] = c - fl;
  }
}

// GL's linear filter over the 2 x 2 x 2 texels around a point: `colour[q]` and `direction[q]`
// point at the pair of texels (x and x + 1) of corner q = (y, z) in the order (0, 0), (1, 0),
// (0, 1), (1, 1); `wyz[q]` its weight, `wx` the two along x. Per channel and x, the four corners'
// weighted texels summed in that order, then the two x sums added: the same float steps on each
// path (this file is built without FMA contraction).
// GCC 12 warns of the `_mm512_undefined_*()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593): off for this function only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
inline void blend(const Texel* const colour[4], const Texel* const direction[4], const float wyz[4],
                  const float wx[2], float outColour[4], float outDirection[4]) {
#if defined(__AVX512F__) && defined(__AVX512DQ__)
  // Lanes 0-3 colour at x, 4-7 colour at x + 1, 8-11 direction at x, 12-15 at x + 1.
  const __m512 w = _mm512_setr_ps(wx[0], wx[0], wx[0], wx[0], wx[1], wx[1], wx[1], wx[1], wx[0],
                                  wx[0], wx[0], wx[0], wx[1], wx[1], wx[1], wx[1]);
  __m512 sum = _mm512_setzero_ps();
  for (int q = 0; q < 4; ++q) {
    const __m256i halves = _mm256_inserti128_si256(
        _mm256_castsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(colour[q]))),
        _mm_loadu_si128(reinterpret_cast<const __m128i*>(direction[q])), 1);
    const __m512 weight = _mm512_mul_ps(_mm512_set1_ps(wyz[q]), w);
    sum = _mm512_add_ps(sum, _mm512_mul_ps(weight, _mm512_cvtph_ps(halves)));
  }
  const __m256 c = _mm512_castps512_ps256(sum), d = _mm512_extractf32x8_ps(sum, 1);
  _mm_storeu_ps(outColour, _mm_add_ps(_mm256_castps256_ps128(c), _mm256_extractf128_ps(c, 1)));
  _mm_storeu_ps(outDirection, _mm_add_ps(_mm256_castps256_ps128(d), _mm256_extractf128_ps(d, 1)));
#elif defined(__F16C__) && defined(__AVX__)
  const __m256 w = _mm256_setr_ps(wx[0], wx[0], wx[0], wx[0], wx[1], wx[1], wx[1], wx[1]);
  __m256 c = _mm256_setzero_ps(), d = _mm256_setzero_ps();
  for (int q = 0; q < 4; ++q) {
    const __m256 weight = _mm256_mul_ps(_mm256_set1_ps(wyz[q]), w);
    c = _mm256_add_ps(c, _mm256_mul_ps(weight, _mm256_cvtph_ps(_mm_loadu_si128(
                                                   reinterpret_cast<const __m128i*>(colour[q])))));
    d = _mm256_add_ps(d,
                      _mm256_mul_ps(weight, _mm256_cvtph_ps(_mm_loadu_si128(
                                                reinterpret_cast<const __m128i*>(direction[q])))));
  }
  _mm_storeu_ps(outColour, _mm_add_ps(_mm256_castps256_ps128(c), _mm256_extractf128_ps(c, 1)));
  _mm_storeu_ps(outDirection, _mm_add_ps(_mm256_castps256_ps128(d), _mm256_extractf128_ps(d, 1)));
#else
  for (std::size_t ch = 0; ch < 4; ++ch) {
    float c[2] = {0, 0}, d[2] = {0, 0};
    for (std::size_t x = 0; x < 2; ++x)
      for (int q = 0; q < 4; ++q) {
        const float weight = wyz[q] * wx[x];
        c[x] = c[x] + weight * fromHalf(colour[q][x][ch]);
        d[x] = d[x] + weight * fromHalf(direction[q][x][ch]);
      }
    outColour[ch] = c[0] + c[1], outDirection[ch] = d[0] + d[1];
  }
#endif
}
#pragma GCC diagnostic pop

}  // namespace

CpuShading::CpuShading(const scene::LightsDesc& desc, const VoxelSums& sums, int terms)
    : desc_(desc),
      sums_(sums),
      terms_(terms),
      wholeShininess_(
          desc.shininess == std::floor(desc.shininess) ? static_cast<int>(desc.shininess) : 0) {}

Vec3 CpuShading::toEye(const Vec3& eye, const Vec3& position) {
  Vec3 u;
  unitTo(eye.x(), eye.y(), eye.z(), position.x(), position.y(), position.z(), u.x(), u.y(), u.z());
  return u;
}

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
  if (desc_.filter == scene::LightFilter::Nearest) {  // lightTexel(floor(g)): zero outside
    const int x = static_cast<int>(std::floor(g[0])), y = static_cast<int>(std::floor(g[1])),
              z = static_cast<int>(std::floor(g[2]));
    if (!inside(x, y, z)) return;
    for (std::size_t c = 0; c < 4; ++c)
      colour[c] = halfToFloat(sums_.colour[at(x, y, z)][c]),
      direction[c] = halfToFloat(sums_.direction[at(x, y, z)][c]);
    return;
  }
  // GL's linear filter with a zero border: the 2 x 2 x 2 voxel centres around g, weights from
  // the fraction past the lower centre, in float as llvmpipe has them for float textures (its
  // results agree to 1e-3, tests/test_lights_shade.cpp; 8-bit weights would not).
  int i[3];
  float f[3];
  for (int a = 0; a < 3; ++a) lowerCentre(g[a], i[a], f[a]);
  trilinear(i, f, colour, direction);
}

inline void CpuShading::trilinear(const int i[3], const float f[3], float colour[4],
                                  float direction[4]) const {
  std::fill(colour, colour + 4, 0.0f), std::fill(direction, direction + 4, 0.0f);
  const VoxelBox& t = sums_.touched;
  if (i[0] + 1 < t.lo[0] || i[0] >= t.hi[0] || i[1] + 1 < t.lo[1] || i[1] >= t.hi[1] ||
      i[2] + 1 < t.lo[2] || i[2] >= t.hi[2])
    return;  // all eight outside (or nothing touched): most pixels where the lights fill a corner
  const float wx[2] = {1.0f - f[0], f[0]};
  float wyz[4];
  for (int q = 0; q < 4; ++q)
    wyz[q] = ((q & 2) ? f[2] : 1.0f - f[2]) * ((q & 1) ? f[1] : 1.0f - f[1]);
  if (i[0] >= t.lo[0] && i[0] + 1 < t.hi[0] && i[1] >= t.lo[1] && i[1] + 1 < t.hi[1] &&
      i[2] >= t.lo[2] && i[2] + 1 < t.hi[2]) {  // all eight inside
    const std::size_t nx = static_cast<std::size_t>(t.hi[0] - t.lo[0]);
    const std::size_t nxy = nx * static_cast<std::size_t>(t.hi[1] - t.lo[1]);
    const std::size_t k = static_cast<std::size_t>(i[2] - t.lo[2]) * nxy +
                          static_cast<std::size_t>(i[1] - t.lo[1]) * nx +
                          static_cast<std::size_t>(i[0] - t.lo[0]);
    const Texel* c[4];
    const Texel* d[4];
    for (std::size_t q = 0; q < 4; ++q) {  // each pair of texels along x lies side by side
      const std::size_t kq = k + (q & 1) * nx + (q >> 1) * nxy;
      c[q] = &sums_.colour[kq], d[q] = &sums_.direction[kq];
    }
    return blend(c, d, wyz, wx, colour, direction);
  }
  onFaces(i, wyz, wx, colour, direction);
}

void CpuShading::onFaces(const int i[3], const float wyz[4], const float wx[2], float colour[4],
                         float direction[4]) const {
  // Voxels outside `touched` (and the volume) read zero: on the box's faces the eight texels are
  // copied, zero outside, and go through the same arithmetic.
  const VoxelBox& t = sums_.touched;
  const std::size_t nx = static_cast<std::size_t>(t.hi[0] - t.lo[0]);
  const std::size_t ny = static_cast<std::size_t>(t.hi[1] - t.lo[1]);
  auto inside = [&](int x, int y, int z) {
    return x >= t.lo[0] && x < t.hi[0] && y >= t.lo[1] && y < t.hi[1] && z >= t.lo[2] &&
           z < t.hi[2];
  };
  auto at = [&](int x, int y, int z) {
    return (static_cast<std::size_t>(z - t.lo[2]) * ny + static_cast<std::size_t>(y - t.lo[1])) *
               nx +
           static_cast<std::size_t>(x - t.lo[0]);
  };
  const Texel* c[4];
  const Texel* d[4];
  Texel pairs[2][4][2]{};
  for (int q = 0; q < 4; ++q) {
    for (int dx = 0; dx < 2; ++dx) {
      const int x = i[0] + dx, y = i[1] + (q & 1), z = i[2] + (q >> 1);
      if (!inside(x, y, z)) continue;
      pairs[0][q][dx] = sums_.colour[at(x, y, z)], pairs[1][q][dx] = sums_.direction[at(x, y, z)];
    }
    c[q] = pairs[0][q], d[q] = pairs[1][q];
  }
  blend(c, d, wyz, wx, colour, direction);
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

void CpuShading::phong(Run& run, std::size_t count) const {
  float(&f)[Run::kFields][Run::kRun] = run.f;
  const float diffuse = (terms_ & 1) ? desc_.diffuse : 0.0f, specular = desc_.specular;
  // particleLight's arithmetic, a lane a pixel: the light vector, the diffuse term (into Br..Bb,
  // the base colour read once) and the reflection's cosine (Re); the colour clamped (Cr..Cb).
#pragma omp simd
  for (std::size_t i = 0; i < count; ++i) {
    const float dx = f[Run::Dx][i], dy = f[Run::Dy][i], dz = f[Run::Dz][i];
    const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const bool lit = len >= 1e-6f;  // else no light: a term of zero (most pixels in a corner)
    const float lx = dx / len, ly = dy / len, lz = dz / len;
    const float nx = f[Run::Nx][i], ny = f[Run::Ny][i], nz = f[Run::Nz][i];
    const float nl = nx * lx + ny * ly + nz * lz, kd = std::max(nl, 0.0f);
    const float cr = lit ? std::max(f[Run::Cr][i], 0.0f) : 0.0f;
    const float cg = lit ? std::max(f[Run::Cg][i], 0.0f) : 0.0f;
    const float cb = lit ? std::max(f[Run::Cb][i], 0.0f) : 0.0f;
    f[Run::Br][i] = lit ? diffuse * (f[Run::Br][i] * cr) * kd : 0.0f;
    f[Run::Bg][i] = lit ? diffuse * (f[Run::Bg][i] * cg) * kd : 0.0f;
    f[Run::Bb][i] = lit ? diffuse * (f[Run::Bb][i] * cb) * kd : 0.0f;
    f[Run::Cr][i] = cr, f[Run::Cg][i] = cg, f[Run::Cb][i] = cb;
    const float twoNl = 2.0f * nl;  // reflect(-l, n) = 2 (n.l) n - l
    const float rx = twoNl * nx - lx, ry = twoNl * ny - ly, rz = twoNl * nz - lz;
    const float re = std::max(rx * f[Run::Ex][i] + ry * f[Run::Ey][i] + rz * f[Run::Ez][i], 0.0f);
    f[Run::Re][i] = lit ? re : 0.0f;
  }
  if (!(terms_ & 2)) return;
  // re^shininess: a whole exponent (the default 16) by squaring, bit by bit for all lanes at once
  // (4 multiplies instead of a libm call; the same to float rounding).
  float* re = f[Run::Re];
  if (wholeShininess_ == 0) {
    for (std::size_t i = 0; i < count; ++i) re[i] = std::pow(re[i], desc_.shininess);
  } else {
    alignas(64) float result[Run::kRun];
    std::fill(result, result + count, 1.0f);
    for (int e = wholeShininess_; e > 0; e >>= 1) {
      if (e & 1)
        for (std::size_t i = 0; i < count; ++i) result[i] *= re[i];
      if (e > 1)
        for (std::size_t i = 0; i < count; ++i) re[i] *= re[i];
    }
    std::copy(result, result + count, re);
  }
  for (std::size_t i = 0; i < count; ++i) {
    f[Run::Br][i] = f[Run::Br][i] + specular * f[Run::Cr][i] * re[i];
    f[Run::Bg][i] = f[Run::Bg][i] + specular * f[Run::Cg][i] * re[i];
    f[Run::Bb][i] = f[Run::Bb][i] + specular * f[Run::Cb][i] * re[i];
  }
}

Vec3 CpuShading::at(const Vec3& position, const Vec3& n, const Vec3& toEye,
                    const Vec3& base) const {
  Run run;
  float(&f)[Run::kFields][Run::kRun] = run.f;
  float g[3], colour[4], direction[4];
  for (int a = 0; a < 3; ++a) {
    g[a] = (position[a] - desc_.origin[a]) / desc_.voxelSize;
    f[Run::Ex + a][0] = toEye[a], f[Run::Nx + a][0] = n[a], f[Run::Br + a][0] = base[a];
  }
  sample(g, colour, direction);
  for (int a = 0; a < 3; ++a) f[Run::Cr + a][0] = colour[a], f[Run::Dx + a][0] = direction[a];
  phong(run, 1);
  return Vec3(f[Run::Br][0], f[Run::Bg][0], f[Run::Bb][0]);
}

void CpuShading::pixels(const frame::GBufferPixels& g, const Vec3& eye, std::uint8_t* rgba) const {
  const frame::Srgb8Table& encode = frame::srgb8Table();
  // NDC -> world in float: a pixel's position within ~1e-5 of its distance of the double
  // product's (the depth's own float steps are of that order), far below a voxel.
  std::array<float, 16> m{};
  for (std::size_t k = 0; k < 16; ++k) m[k] = static_cast<float>(g.fromNdc[k]);
  const float ox = desc_.origin.x(), oy = desc_.origin.y(), oz = desc_.origin.z();
  const float h = desc_.voxelSize, perVoxel = 1.0f / h, ex = eye.x(), ey = eye.y(), ez = eye.z();
  const std::size_t width = static_cast<std::size_t>(g.width);
  const float sx = 2.0f / static_cast<float>(g.width);
  const bool trilinearOnce =
      desc_.filter == scene::LightFilter::Trilinear && desc_.oversampling <= 1;
  parallelForDynamic(static_cast<std::size_t>(g.height), 1, [&](std::size_t row) {
    Run run;
    float(&f)[Run::kFields][Run::kRun] = run.f;
    const float ndcY = 2.0f * (static_cast<float>(row) + 0.5f) / static_cast<float>(g.height) - 1;
    for (std::size_t first = 0; first < width; first += Run::kRun) {
      const std::size_t n = std::min(Run::kRun, width - first), i0 = row * width + first;
      const float* depth = g.depth + i0;
      // The block's positions, voxel coordinates and vectors to the eye, a lane a column (the
      // undrawn ones too: they are not read).
      if (g.position) {
        const float* p = g.position + 4 * i0;
#pragma omp simd
        for (std::size_t k = 0; k < n; ++k) {
          f[Run::Gx][k] = (p[4 * k] - ox) / h, f[Run::Gy][k] = (p[4 * k + 1] - oy) / h,
          f[Run::Gz][k] = (p[4 * k + 2] - oz) / h;
          unitTo(ex, ey, ez, p[4 * k], p[4 * k + 1], p[4 * k + 2], f[Run::Ex][k], f[Run::Ey][k],
                 f[Run::Ez][k]);
        }
      } else {
#pragma omp simd
        for (std::size_t k = 0; k < n; ++k) {
          // The pixel's centre back through the frame's matrices: NDC -> world.
          const float x = sx * (static_cast<float>(first + k) + 0.5f) - 1.0f;
          const float z = 2.0f * depth[k] - 1.0f;
          float p[4];
          for (std::size_t r = 0; r < 4; ++r)
            p[r] = m[r] * x + m[4 + r] * ndcY + m[8 + r] * z + m[12 + r];
          const float w = 1.0f / p[3];  // products, not divisions: ~1 ulp, far below the depth's
          const float px = p[0] * w, py = p[1] * w, pz = p[2] * w;
          f[Run::Gx][k] = (px - ox) * perVoxel, f[Run::Gy][k] = (py - oy) * perVoxel,
          f[Run::Gz][k] = (pz - oz) * perVoxel;
          unitTo(ex, ey, ez, px, py, pz, f[Run::Ex][k], f[Run::Ey][k], f[Run::Ez][k]);
        }
      }
      for (std::size_t a = 0; a < 3; ++a)
        lowerCentres(f[Run::Gx + a], run.lower[a], f[Run::Fx + a], static_cast<int>(n));
      // The drawn pixels packed (in place: a pixel's slot is at most its column), sampled.
      std::size_t lit = 0;
      for (std::size_t k = 0; k < n; ++k) {
        std::uint8_t* out = rgba + 4 * (i0 + k);
        if (depth[k] >= 1.0f) {  // nothing drawn here (the depth is cleared to 1 each frame)
          out[0] = out[1] = out[2] = out[3] = 0;
          continue;
        }
        const float gk[3] = {f[Run::Gx][k], f[Run::Gy][k], f[Run::Gz][k]};
        float colour[4], direction[4];
        if (trilinearOnce) {
          const int lower[3] = {run.lower[0][k], run.lower[1][k], run.lower[2][k]};  // NOLINT
          const float fraction[3] = {f[Run::Fx][k], f[Run::Fy][k], f[Run::Fz][k]};
          trilinear(lower, fraction, colour, direction);
        } else {
          sample(gk, colour, direction);
        }
        const float* nn = g.normal + 4 * (i0 + k);
        const std::uint16_t* b = g.albedo + 4 * (i0 + k);
        for (int a = 0; a < 3; ++a) {
          f[Run::Ex + a][lit] = f[Run::Ex + a][k], f[Run::Nx + a][lit] = nn[a];
          f[Run::Br + a][lit] = halfToFloat(b[a]);
          f[Run::Cr + a][lit] = colour[a], f[Run::Dx + a][lit] = direction[a];
        }
        run.column[lit++] = static_cast<std::uint16_t>(k);
      }
      phong(run, lit);
      for (std::size_t j = 0; j < lit; ++j) {
        const std::size_t i = i0 + run.column[j];
        const float* l = g.lit + 4 * i;
        std::uint8_t* out = rgba + 4 * i;
        for (int a = 0; a < 3; ++a) out[a] = encode(l[a] + f[Run::Br + a][j]);
        out[3] = 255;
      }
    }
  });
}

}  // namespace sph::render::lights
