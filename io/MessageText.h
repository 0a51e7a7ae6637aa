// Pieces of the one-line error messages (STYLE.md rule 10): user text quoted safely and numbers
// printed readably. Input can be hostile (a 100 MB number, a UTF-16 file, a key with control
// bytes), and a message must stay one short printable line whatever it quotes.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace sph::io {

// `text` for quoting in a message: bytes outside printable ASCII as \xHH, and cut to `max`
// characters with "..." when longer. No quotes added.
std::string printable(std::string_view text, std::size_t max = 40);

// A file path for quoting in a message: as printable(), but whole up to 240 characters, since a
// path cut at 40 loses its file name - the part a user needs - under a deep directory.
inline std::string printablePath(std::string_view path) {
  return printable(path, 240);
}

// `text` as one line a terminal shows as it is: valid UTF-8 kept (accents, other scripts), control
// bytes (a newline, ESC, DEL, the C1 controls) and bytes that are not UTF-8 as \xHH. Every line
// the program prints with a name in it (an error, a path, a scene's name) goes through it.
std::string oneLine(std::string_view text);
// Whether oneLine() would change `text`.
bool hasControlBytes(std::string_view text);

// "wrote WHAT" on stderr, WHAT made one line (oneLine): how every command says it wrote a file
// (WHAT starts with its path, then what it holds). stderr, because stdout may carry the data
// itself (`export -o -`) and the progress lines are there too.
void sayWritten(std::string_view what);

// A number as a person reads it, %g style with `digits` significant digits and a short exponent:
// 0.25, 1500, 1e6, 1.79769e308, -3.5e-5, inf, nan. Never a 300-digit expansion.
std::string readableNumber(double v, int digits = 6);

// A count that may be huge: exact up to a million, then two significant digits ("1.9e8").
std::string readableCount(double n);

}  // namespace sph::io
