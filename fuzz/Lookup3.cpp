#include "fuzz/Lookup3.h"

namespace sph::fuzz {
namespace {

std::uint32_t rotate(std::uint32_t x, int k) {
  return (x << k) | (x >> (32 - k));
}

void mix(std::uint32_t& a, std::uint32_t& b, std::uint32_t& c) {
  a -= c, a ^= rotate(c, 4), c += b;
  b -= a, b ^= rotate(a, 6), a += c;
  c -= b, c ^= rotate(b, 8), b += a;
  a -= c, a ^= rotate(c, 16), c += b;
  b -= a, b ^= rotate(a, 19), a += c;
  c -= b, c ^= rotate(b, 4), b += a;
}

void finish(std::uint32_t& a, std::uint32_t& b, std::uint32_t& c) {
  c ^= b, c -= rotate(b, 14);
  a ^= c, a -= rotate(c, 11);
  b ^= a, b -= rotate(a, 25);
  c ^= b, c -= rotate(b, 16);
  a ^= c, a -= rotate(c, 4);
  b ^= a, b -= rotate(a, 14);
  c ^= b, c -= rotate(b, 24);
}

// Bytes i..i+3 of `k` as a little-endian word, those past `n` counting as zero.
std::uint32_t word(const std::uint8_t* k, std::size_t n) {
  std::uint32_t w = 0;
  for (std::size_t i = 0; i < 4 && i < n; ++i) w |= static_cast<std::uint32_t>(k[i]) << (8 * i);
  return w;
}

}  // namespace

std::uint32_t lookup3(const std::uint8_t* data, std::size_t length, std::uint32_t seed) {
  std::uint32_t a = 0xdeadbeef + static_cast<std::uint32_t>(length) + seed;
  std::uint32_t b = a, c = a;
  while (length > 12) {
    a += word(data, 4), b += word(data + 4, 4), c += word(data + 8, 4);
    mix(a, b, c);
    data += 12, length -= 12;
  }
  if (length == 0) return c;  // the last block is always whole: nothing left to add
  a += word(data, length);
  if (length > 4) b += word(data + 4, length - 4);
  if (length > 8) c += word(data + 8, length - 8);
  finish(a, b, c);
  return c;
}

}  // namespace sph::fuzz
