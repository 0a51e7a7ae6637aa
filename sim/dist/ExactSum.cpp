#include "sim/dist/ExactSum.h"

#include <cmath>

namespace sph::dist {

void ExactSum::add(float value) {
  if (value == 0) return;
  int exponent = 0;
  // value = m * 2^(exponent - 24) with |m| an integer below 2^24.
  const double fraction = std::frexp(static_cast<double>(value), &exponent);
  const std::int64_t m = static_cast<std::int64_t>(std::ldexp(fraction, 24));
  const int shift = exponent - 24 + 149;  // bit position of m's lowest bit, >= 0 for floats
  const int digit = shift / 32, bit = shift % 32;
  // m << bit spans at most 56 bits: two digits.
  const std::int64_t shifted = m * (std::int64_t(1) << bit);
  const std::int64_t low = shifted & 0xffffffff;  // two's complement: low part >= 0
  digits_[digit] += low;
  if (digit + 1 < kDigits) digits_[digit + 1] += (shifted - low) / (std::int64_t(1) << 32);
  if (++pending_ >= (1u << 30)) normalise();
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

}  // namespace sph::dist
