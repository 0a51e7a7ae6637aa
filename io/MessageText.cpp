#include "io/MessageText.h"

#include <cmath>
#include <cstdint>
#include <cstdio>

namespace sph::io {

std::string printable(std::string_view text, std::size_t max) {
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      out += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", byte);
      out += escaped;
    }
    if (out.size() > max) break;
  }
  if (out.size() > max) {
    out.resize(max > 3 ? max - 3 : 0);
    out += "...";
  }
  return out;
}

namespace {

// The length of the UTF-8 character at `text[i]` if it is a valid one and no control (C1 controls
// are U+0080-U+009F), else 0.
std::size_t printableCharacter(std::string_view text, std::size_t i) {
  const auto at = [&](std::size_t k) { return static_cast<unsigned char>(text[i + k]); };
  const unsigned char b = at(0);
  if (b >= 0x20 && b < 0x7f) return 1;
  std::size_t n = 0;
  std::uint32_t code = 0;
  if (b >= 0xc2 && b <= 0xdf) n = 2, code = b & 0x1f;
  else if (b >= 0xe0 && b <= 0xef) n = 3, code = b & 0x0f;
  else if (b >= 0xf0 && b <= 0xf4) n = 4, code = b & 0x07;
  else return 0;
  if (i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((at(k) & 0xc0) != 0x80) return 0;
    code = (code << 6) | (at(k) & 0x3f);
  }
  const std::uint32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < least[n] || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return 0;
  if (code >= 0x80 && code <= 0x9f) return 0;
  return n;
}

}  // namespace

std::string oneLine(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    if (const std::size_t n = printableCharacter(text, i); n > 0) {
      out.append(text.substr(i, n));
      i += n;
      continue;
    }
    char escaped[8];
    std::snprintf(escaped, sizeof escaped, "\\x%02X", static_cast<unsigned char>(text[i]));
    out += escaped;
    ++i;
  }
  return out;
}

bool hasControlBytes(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = printableCharacter(text, i);
    if (n == 0) return true;
    i += n;
  }
  return false;
}

std::string readableNumber(double v, int digits) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  // "1e+06" -> "1e6", "2.5e-05" -> "2.5e-5": the exponent as JSON and people write it.
  std::string s = buf;
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  if (exponent[0] == '+' || exponent[0] == '-') exponent.erase(0, 1);
  while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
  return s.substr(0, e) + "e" + (negative ? "-" : "") + exponent;
}

std::string readableCount(double n) {
  if (std::isfinite(n) && std::fabs(n) < 1e6) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", n);
    return buf;
  }
  return readableNumber(n, 2);
}

void sayWritten(std::string_view what) {
  std::fprintf(stderr, "wrote %s\n", oneLine(what).c_str());
}

}  // namespace sph::io
