#include "sim/ranks/ExactSum.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "sim/Parallel.h"

namespace sph::ranks {

namespace {

// A finite float is m 2^(e - 150) for its 8-bit biased exponent e > 0 and 24-bit significand m
// (the implicit bit set), or m 2^-149 for e = 0 (subnormal): its signed m.
std::int64_t significand(std::uint32_t bits, std::uint32_t e) {
  const std::int64_t m = (bits & 0x7fffff) | (e ? 0x800000 : 0);
  return (bits >> 31) ? -m : m;
}
std::uint32_t exponentOf(std::uint32_t bits) {
  return (bits >> 23) & 0xff;
}
// The bit of the fixed-point value (weight 2^-149) that m's lowest bit lands on.
int shiftOf(std::uint32_t e) {
  return e == 0 ? 0 : static_cast<int>(e) - 1;
}
// Below this many values one thread sums faster than a parallel region starts.
constexpr std::size_t kThreadedLength = 1 << 15;

}  // namespace

void ExactSum::add(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  const std::uint32_t e = exponentOf(bits);
  const std::int64_t m = significand(bits, e);
  if (m != 0) addShifted(m, shiftOf(e));
}

void ExactSum::addShifted(std::int64_t value, int shift) {
  // value = high 2^32 + low with 0 <= low < 2^32, each shifted by at most 31 bits: both fit.
  const std::int64_t low = value & 0xffffffff, high = (value - low) / (std::int64_t(1) << 32);
  const int digit = shift / 32, bit = shift % 32;
  for (const auto& [part, at] : {std::pair{low, digit}, std::pair{high, digit + 1}}) {
    if (part == 0 || at >= kDigits) continue;
    const std::int64_t shifted = part * (std::int64_t(1) << bit);
    const std::int64_t lowBits = shifted & 0xffffffff;
    digits_[at] += lowBits;
    if (at + 1 < kDigits) digits_[at + 1] += (shifted - lowBits) / (std::int64_t(1) << 32);
  }
  // A digit may gain up to 2^33 here (two parts), twice add()'s.
  pending_ += 2;
  if (pending_ >= (1u << 30)) normalise();
}

void ExactSum::addAll(const float* v, std::size_t n, const std::uint8_t* skip) {
  // One integer sum per exponent (2^39 significands of 2^24 fit in 63 bits), then 256 shifts.
  // A long array (DFSPH's error, whose mean follows each of its passes) on every thread, a sum
  // per exponent each: integer sums, so how the array is split changes nothing.
  using ByExponent = std::array<std::int64_t, 256>;
  auto sumRange = [&](std::size_t from, std::size_t to, ByExponent& byExponent) {
    for (std::size_t i = from; i < to; ++i) {
      if (skip && skip[i]) continue;
      std::uint32_t bits;
      std::memcpy(&bits, &v[i], sizeof bits);
      const std::uint32_t e = exponentOf(bits);
      byExponent[e] += significand(bits, e);
    }
  };
  ByExponent total{};
  const std::size_t parts = n >= kThreadedLength ? static_cast<std::size_t>(threadCount()) : 1;
  if (parts == 1) {
    sumRange(0, n, total);
  } else {
    std::vector<ByExponent> part(parts, ByExponent{});
    parallelFor(parts,
                [&](std::size_t p) { sumRange(n * p / parts, n * (p + 1) / parts, part[p]); });
    for (const ByExponent& sums : part)
      for (std::size_t e = 0; e < total.size(); ++e) total[e] += sums[e];
  }
  for (std::uint32_t e = 0; e < 256; ++e)
    if (total[e] != 0) addShifted(total[e], shiftOf(e));
}

void ExactSum::merge(const Digits& other) {
  for (int d = 0; d < kDigits; ++d) digits_[d] += other[d];
  normalise();
}

void ExactSum::normalise() {
  for (int d = 0; d + 1 < kDigits; ++d) {
    const std::int64_t low = digits_[d] & 0xffffffff;
    digits_[d + 1] += (digits_[d] - low) / (std::int64_t(1) << 32);
    digits_[d] = low;
  }
  pending_ = 0;
}

double ExactSum::toDouble() const {
  ExactSum n = *this;
  n.normalise();
  // Highest digit first: the leading digits carry the value, the rest only round it.
  double sum = 0;
  for (int d = kDigits - 1; d >= 0; --d) {
    sum += std::ldexp(static_cast<double>(n.digits_[d]), 32 * d - 149);
  }
  return sum;
}

void sumOverRanks(Communicator& ranks, ExactSum& sum, std::int64_t& count) {
  sum.normalise();
  std::vector<std::int64_t> all(sum.digits().begin(), sum.digits().end());
  all.push_back(count);
  ranks.sumInPlace(all);
  std::copy(all.begin(), all.end() - 1, sum.digits().begin());
  count = all.back();
}

}  // namespace sph::ranks
