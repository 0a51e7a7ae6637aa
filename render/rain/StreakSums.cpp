#include "render/rain/StreakSums.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <omp.h>

#include "render/rain/ExpNear.h"
#include "sim/Assert.h"

#if defined(__AVX512F__)
// GCC 12 warns of the `_mm512_undefined_*()` that its own AVX-512 intrinsics pass as the unused
// source of unmasked operations (a false positive, GCC bug 105593).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace sph::render::rain {
namespace {

// Fixed point of the sums: b_i (at most -ln(0.01) = 4.6, see add()) in units of 2^-18, so a pixel
// holds up to 8,192 in int32 - ~1,800 opaque lines - and a line's b is kept to 4e-6.
constexpr float kScale = 262144.0f;
// Entries of the table of b = -ln(1 - a) (valueOf()): linear between them it is within 2e-4 of b
// at a = 0.99 and 1e-7 at a = 0.5. logf took a tenth of the tier's time.
constexpr int kWeights = 4096;

// One pixel of the layer from its sums p: L = (p0, p1, p2) (1 - T) / p3, T = exp(-p3 / kScale),
// and (0, 0, 0, 1) where no line is. For the builds without AVX-512 (resolvePixels() below: the
// same operations, the same bits).
[[maybe_unused]] void resolvePixel(const std::int32_t* p, float* q) {
  if (p[3] <= 0) {
    q[0] = q[1] = q[2] = 0, q[3] = 1;
    return;
  }
  const float weights = static_cast<float>(p[3]);
  const float t = expNear(weights * (-1.0f / kScale));
  const float k = (1 - t) / weights;
  q[0] = static_cast<float>(p[0]) * k, q[1] = static_cast<float>(p[1]) * k;
  q[2] = static_cast<float>(p[2]) * k, q[3] = t;
}

#if defined(__AVX512F__)
// resolvePixel() for the 4 pixels of `sums` (a 128-bit lane each, its 4 sums), into `out`
// where `mask` (16 bits, 4 a pixel) is set.
void resolvePixels(__m512i sums, float* out, __mmask16 mask) {
  const __m512 weights = _mm512_cvtepi32_ps(_mm512_shuffle_epi32(sums, _MM_PERM_DDDD));
  const __m512 t = expNear(_mm512_mul_ps(weights, _mm512_set1_ps(-1.0f / kScale)));
  // No line (weights 0): k = 0, so L = 0, and t = exp(0) = 1 exactly.
  const __mmask16 lit = _mm512_cmp_ps_mask(weights, _mm512_setzero_ps(), _CMP_GT_OQ);
  const __m512 k = _mm512_maskz_div_ps(lit, _mm512_sub_ps(_mm512_set1_ps(1.0f), t), weights);
  const __m512 light = _mm512_mul_ps(_mm512_cvtepi32_ps(sums), k);
  _mm512_mask_storeu_ps(out, mask, _mm512_mask_blend_ps(0x8888, light, t));
}
#endif

}  // namespace

StreakSums::StreakSums() : weights_(kWeights + 2) {
  for (int i = 0; i < kWeights + 2; ++i)
    weights_[static_cast<std::size_t>(i)] =
        static_cast<float>(-std::log1p(-std::min(0.99, i / static_cast<double>(kWeights))));
}

void StreakSums::setImages(const std::vector<float>& alpha, const std::vector<float>& profile,
                           int layers, int w, int h) {
  const int pw = w + 2, ph = h + 2;
  // Each profile's mean along the streak, as the lines fetch it (s in [0, 1] at padded texel row
  // s h + 0.5, linear between rows), by the midpoint rule over 4,096 steps.
  meanAlong_.assign(static_cast<std::size_t>(layers), 0.0f);
  constexpr int kSteps = 4096;
  for (int l = 0; l < layers; ++l) {
    const float* p = profile.data() + static_cast<std::size_t>(l) * ph;
    double sum = 0;
    for (int k = 0; k < kSteps; ++k) {
      const double t = (k + 0.5) / kSteps * h + 0.5;
      const int t0 = static_cast<int>(t);
      sum += p[t0] + (t - t0) * (p[t0 + 1] - p[t0]);
    }
    meanAlong_[static_cast<std::size_t>(l)] = static_cast<float>(sum / kSteps);
  }
  // A streak k (2..8) pixels wide is k lines side by side, line j taking the strip [j / k,
  // (j + 1) / k) across the image: each strip's mean (the image along the streak averaged as
  // above, bilinear across it as the exact streaks fetch it).
  stripMean_.assign(static_cast<std::size_t>(layers) * kStripTable, 0.0f);
  for (int l = 0; l < layers; ++l) {
    std::vector<double> column(static_cast<std::size_t>(pw), 0.0);  // padded columns, along-mean
    for (int c = 0; c < pw; ++c) {
      for (int k = 0; k < kSteps; ++k) {
        const double t = (k + 0.5) / kSteps * h + 0.5;
        const int t0 = static_cast<int>(t);
        const float* a = alpha.data() + (static_cast<std::size_t>(l) * ph + t0) * pw + c;
        column[static_cast<std::size_t>(c)] += a[0] + (t - t0) * (a[pw] - a[0]);
      }
      column[static_cast<std::size_t>(c)] /= kSteps;
    }
    const auto across = [&](double u) {  // u in [0, 1] across the width
      const double ts = u * w + 0.5;
      const int s0 = std::min(static_cast<int>(ts), pw - 2);
      return column[s0] + (ts - s0) * (column[s0 + 1] - column[s0]);
    };
    for (int k = 1; k <= kMaxStrips; ++k) {
      float* strips = stripMean_.data() + static_cast<std::size_t>(l) * kStripTable +
                      static_cast<std::size_t>(k * (k - 1) / 2);
      double total = 0;
      for (int j = 0; j < k; ++j) {
        constexpr int kSamples = 64;
        double sum = 0;
        for (int m = 0; m < kSamples; ++m) sum += across((j + (m + 0.5) / kSamples) / k);
        strips[j] = static_cast<float>(sum / kSamples);
        total += strips[j];
      }
      const double scale = total > 0 ? meanAlong_[static_cast<std::size_t>(l)] * k / total : 0;
      for (int j = 0; j < k; ++j) strips[j] = static_cast<float>(strips[j] * scale);
    }
  }
}

std::uint64_t StreakSums::addWide(int thread, const Line& line, int first, int end, const Vec3& c,
                                  int layer) {
  const int strips = std::min(kMaxStrips, static_cast<int>(std::ceil(line.coverage)));
  const float* mean = stripMean_.data() + static_cast<std::size_t>(layer) * kStripTable +
                      static_cast<std::size_t>(strips * (strips - 1) / 2);
  const float step = line.coverage / static_cast<float>(strips);
  std::uint64_t fragments = 0;
  for (int j = 0; j < strips; ++j) {
    Line strip = line;
    strip.xt += (static_cast<float>(j) + 0.5f) * step - 0.5f * line.coverage;
    fragments += add(thread, strip, first, end, c, step * mean[j]);
  }
  return fragments;
}

void StreakSums::begin(int width, int height, const float* depth, int threads) {
  SPH_ASSERT(height < 65536);  // a run's rows are 16 bits (Run)
  width_ = width, height_ = height, depth_ = depth;
  threads_ = threads;
  stripCount_ = (width + kStrip - 1) / kStrip;
  // Cleared, not freed: the lists keep their capacity from frame to frame, but for a list more than
  // four times larger than its last frame's runs (the rain moved across the screen, or fewer
  // drops): without this, memory would be every list's peak, up to a strip holding all the runs.
  lists_.resize(static_cast<std::size_t>(threads) * stripCount_);
  constexpr std::size_t kAlwaysKept = 4096;  // runs (64 KiB)
  for (auto& list : lists_) {
    const std::size_t used = list.size();
    list.clear();
    if (list.capacity() > kAlwaysKept && list.capacity() > 4 * used) {
      std::vector<Run> smaller;
      smaller.reserve(2 * used);
      list.swap(smaller);
    }
  }
  const int tiles = (height + kTileRows - 1) / kTileRows;
  nearest_.resize(static_cast<std::size_t>(tiles) * width);
#pragma omp parallel for schedule(static)
  for (int tile = 0; tile < tiles; ++tile) {
    float* nearest = nearest_.data() + static_cast<std::size_t>(tile) * width;
    const int first = tile * kTileRows, end = std::min(height, first + kTileRows);
    std::copy(depth + static_cast<std::size_t>(first) * width,
              depth + static_cast<std::size_t>(first + 1) * width, nearest);
    for (int r = first + 1; r < end; ++r) {
      const float* row = depth + static_cast<std::size_t>(r) * width;
#pragma omp simd
      for (int x = 0; x < width; ++x) nearest[x] = std::min(nearest[x], row[x]);
    }
  }
}

void StreakSums::addRun(int thread, int column, int first, int end, const std::int32_t* v) {
  const int strip = column / kStrip, x = column - strip * kStrip;
  for (int k = 0; k < 4; ++k) SPH_ASSERT(v[k] >= 0 && v[k] < (1 << kValueBits));
  const auto value = [&](int k) { return static_cast<std::uint64_t>(v[k]); };
  const Run run{value(0) | value(1) << kValueBits | value(2) << (2 * kValueBits),
                value(3) | static_cast<std::uint64_t>(x) << kValueBits |
                    static_cast<std::uint64_t>(first) << (kValueBits + 5) |
                    static_cast<std::uint64_t>(end) << (kValueBits + 21)};
  std::vector<Run>& list = lists_[static_cast<std::size_t>(thread) * stripCount_ + strip];
  list.push_back(run);
  // The list's next lines asked for now: the stores of a run wait less for them.
  __builtin_prefetch(list.data() + list.size() + 8, 1);
}

inline bool StreakSums::valueOf(const Vec3& c, float alpha, std::int32_t* v) const {
  // b = -ln(1 - a), a at most 0.99: a line is never quite opaque, so T = exp(-sum b) > 0 and the
  // colour sum over the b sum stays defined.
  const float x = std::clamp(alpha, 0.0f, 0.99f) * kWeights;
  const int i = static_cast<int>(x);
  const float* w = weights_.data() + i;
  const float b = w[0] + (x - static_cast<float>(i)) * (w[1] - w[0]);
  v[0] = static_cast<std::int32_t>(b * c.x() * kScale + 0.5f);
  v[1] = static_cast<std::int32_t>(b * c.y() * kScale + 0.5f);
  v[2] = static_cast<std::int32_t>(b * c.z() * kScale + 0.5f);
  v[3] = static_cast<std::int32_t>(b * kScale + 0.5f);
  return v[3] > 0;
}

std::uint64_t StreakSums::addLines(int thread, const Lines& lines, int count, const Vec3* colour,
                                   const float* alpha) {
  std::uint64_t fragments = 0;
  for (int k = 0; k < count; ++k) {
    const int first = lines.first[k], end = lines.end[k];
    if (!lines.ok[k] || end <= first || lines.coverage[k] > 1) continue;
    std::int32_t v[4];
    if (!valueOf(colour[k], alpha[k], v)) continue;
    const auto sAt = [&](int row) {
      return std::min(
          std::max(0.0f, (static_cast<float>(row) + 0.5f - lines.yt[k]) * lines.invDy[k]), 1.0f);
    };
    const float s0 = sAt(first), s1 = sAt(end - 1);
    const float x0 = lines.xt[k] + s0 * lines.dx[k], x1 = lines.xt[k] + s1 * lines.dx[k];
    const float w = static_cast<float>(width_);
    // Both ends inside: the cast truncates towards zero, so an x1 in (-1, 0) would pass as
    // column 0 and add the rows left of the frame.
    const bool inside = x0 >= 0 && x0 < w && x1 >= 0 && x1 < w;
    const int column = inside ? static_cast<int>(x0) : -1;
    bool whole = inside && column == static_cast<int>(x1);
    if (whole) {  // one column: in front of the frame there?
      const float zFar = std::max(lines.zt[k] + s0 * lines.dz[k], lines.zt[k] + s1 * lines.dz[k]);
      float nearest = 2;
      for (int tile = first / kTileRows; tile <= (end - 1) / kTileRows; ++tile)
        nearest = std::min(nearest, nearest_[static_cast<std::size_t>(tile) * width_ + column]);
      whole = zFar < nearest;
    }
    if (!whole) {  // partly outside the frame, over several columns, or partly hidden
      fragments += add(thread, lines[k], first, end, colour[k], alpha[k]);
      continue;
    }
    addRun(thread, column, first, end, v);
    fragments += static_cast<std::uint64_t>(end - first);
  }
  return fragments;
}

std::uint64_t StreakSums::add(int thread, const Line& line, int first, int end, const Vec3& c,
                              float alpha) {
  if (first >= end) return 0;  // no rows (a run's rows must lie in the strip's buffer)
  std::int32_t v[4];
  if (!valueOf(c, alpha, v)) return 0;
  // The line's pixel in a row, as the lines' rows take it (StreakLine.cpp, rowsOneByOne): -1 left
  // of the frame, width_ right of it. Monotonic in the row, so equal at both ends means one column.
  const auto sAt = [&](int row) {
    return std::min(std::max(0.0f, (static_cast<float>(row) + 0.5f - line.yt) * line.invDy), 1.0f);
  };
  const auto columnAt = [&](int row) {
    const float x = line.xt + sAt(row) * line.dx;
    return x < 0 ? -1 : x >= static_cast<float>(width_) ? width_ : static_cast<int>(x);
  };
  std::uint64_t fragments = 0;
  // One run of rows [r0, r1) in `column`, depth tested.
  const auto run = [&](int column, int r0, int r1) {
    if (column < 0 || column >= width_) return;
    const float z0 = line.zt + sAt(r0) * line.dz, z1 = line.zt + sAt(r1 - 1) * line.dz;
    float nearest = 2;
    for (int tile = r0 / kTileRows; tile <= (r1 - 1) / kTileRows; ++tile)
      nearest = std::min(nearest, nearest_[static_cast<std::size_t>(tile) * width_ + column]);
    if (std::max(z0, z1) < nearest) {
      addRun(thread, column, r0, r1, v);
      fragments += static_cast<std::uint64_t>(r1 - r0);
      return;
    }
    int open = -1;  // first row of the visible part being collected
    for (int row = r0; row < r1; ++row) {
      const bool keep =
          line.zt + sAt(row) * line.dz < depth_[static_cast<std::size_t>(row) * width_ + column];
      if (keep && open < 0) open = row;
      if (!keep && open >= 0)
        addRun(thread, column, open, row, v), fragments += row - open, open = -1;
    }
    if (open >= 0) addRun(thread, column, open, r1, v), fragments += r1 - open;
  };
  const int firstColumn = columnAt(first), lastColumn = columnAt(end - 1);
  if (firstColumn == lastColumn) {
    run(firstColumn, first, end);
    return fragments;
  }
  int runStart = first, column = firstColumn;
  for (int row = first + 1; row < end; ++row) {
    const int next = columnAt(row);
    if (next == column) continue;
    run(column, runStart, row);
    runStart = row, column = next;
  }
  run(column, runStart, end);
  return fragments;
}

std::size_t StreakSums::runCapacity() const {
  std::size_t room = 0;
  for (const auto& list : lists_) room += list.capacity();
  return room;
}

void StreakSums::resolve(float* layer) {
  runs_ = 0;
  for (const auto& list : lists_) runs_ += list.size();
  const std::size_t stripSize = 4 * static_cast<std::size_t>(kStrip) * height_;
#pragma omp parallel
  {
#pragma omp single
    strips_.resize(std::max(strips_.size(), static_cast<std::size_t>(omp_get_num_threads())));
    std::vector<std::int32_t>& sums = strips_[static_cast<std::size_t>(omp_get_thread_num())];
    if (sums.size() != stripSize) sums.assign(stripSize, 0);
#pragma omp for schedule(dynamic, 1)
    for (int strip = 0; strip < stripCount_; ++strip) {
      // Every thread's runs of the strip into its buffer: integer sums, the same in any order.
      for (int t = 0; t < threads_; ++t) {
        const std::vector<Run>& list = lists_[static_cast<std::size_t>(t) * stripCount_ + strip];
        for (const Run& run : list) {
          constexpr std::uint64_t kMask = (std::uint64_t{1} << kValueBits) - 1;
          const auto field = [](std::uint64_t w, int shift, std::uint64_t mask) {
            return static_cast<std::int32_t>((w >> shift) & mask);
          };
          const std::int32_t v[4] = {field(run.lo, 0, kMask), field(run.lo, kValueBits, kMask),
                                     field(run.lo, 2 * kValueBits, kMask), field(run.hi, 0, kMask)};
          const int x = field(run.hi, kValueBits, 31);
          const int first = field(run.hi, kValueBits + 5, 0xffff);
          const int end = field(run.hi, kValueBits + 21, 0xffff);
          std::int32_t* start = sums.data() + 4 * static_cast<std::size_t>(first * kStrip + x);
          std::int32_t* stop = end < height_
                                   ? sums.data() + 4 * static_cast<std::size_t>(end * kStrip + x)
                                   : nullptr;
#if defined(__SSE2__)
          // The 4 sums of a pixel as one vector.
          const __m128i add = _mm_loadu_si128(reinterpret_cast<const __m128i*>(v));
          auto* p = reinterpret_cast<__m128i*>(start);
          _mm_storeu_si128(p, _mm_add_epi32(_mm_loadu_si128(p), add));
          if (stop == nullptr) continue;
          auto* q = reinterpret_cast<__m128i*>(stop);
          _mm_storeu_si128(q, _mm_sub_epi32(_mm_loadu_si128(q), add));
#else
          for (int c = 0; c < 4; ++c) start[c] += v[c];
          if (stop == nullptr) continue;
          for (int c = 0; c < 4; ++c) stop[c] -= v[c];
#endif
        }
      }
      // Down the columns with their running sums, leaving the buffer zeroed.
      const int x0 = strip * kStrip, columns = std::min(kStrip, width_ - x0);
#if defined(__AVX512F__)
      // The strip's row as 8 vectors of 4 pixels, its running sums in registers.
      constexpr int kVectors = kStrip / 4;
      __m512i running[kVectors];
      __mmask16 masks[kVectors];
      for (int j = 0; j < kVectors; ++j) {
        running[j] = _mm512_setzero_si512();
        const int lanes = std::clamp(4 * (columns - 4 * j), 0, 16);
        masks[j] = static_cast<__mmask16>((1u << lanes) - 1);
      }
      for (int r = 0; r < height_; ++r) {
        std::int32_t* s = sums.data() + 4 * static_cast<std::size_t>(r) * kStrip;
        float* out = layer + 4 * (static_cast<std::size_t>(r) * width_ + x0);
        for (int j = 0; j < kVectors; ++j) {
          running[j] = _mm512_add_epi32(running[j], _mm512_loadu_si512(s + 16 * j));
          _mm512_storeu_si512(s + 16 * j, _mm512_setzero_si512());
          if (masks[j] != 0) resolvePixels(running[j], out + 16 * j, masks[j]);
        }
      }
#else
      alignas(64) std::int32_t running[4 * kStrip] = {};
      for (int r = 0; r < height_; ++r) {
        std::int32_t* s = sums.data() + 4 * static_cast<std::size_t>(r) * kStrip;
#pragma omp simd
        for (int i = 0; i < 4 * columns; ++i) running[i] += s[i], s[i] = 0;
        float* out = layer + 4 * (static_cast<std::size_t>(r) * width_ + x0);
        for (int x = 0; x < columns; ++x) resolvePixel(running + 4 * x, out + 4 * x);
      }
#endif
    }
  }
}

}  // namespace sph::render::rain
