#include "io/scene/JsonText.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <vector>

#include "io/MessageText.h"
#include "sim/InputError.h"

namespace sph::io::scene {
namespace {

using nlohmann::json;

[[noreturn]] void failAt(const std::string& where, const std::string& text, std::size_t offset,
                         const std::string& message) {
  throw InputError(where + ":" + lineColumn(text, offset) + ": " + message);
}

// Length of the UTF-8 sequence starting at `i`, or 0 if it is not a valid one (overlong forms,
// surrogates and code points past U+10FFFF are invalid, RFC 3629 section 4).
std::size_t utf8Length(const std::string& s, std::size_t i) {
  const auto at = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = at(i);
  if (b < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    if (b == 0xE0) lo = 0xA0;  // overlong
    if (b == 0xED) hi = 0x9F;  // surrogates
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    if (b == 0xF0) lo = 0x90;  // overlong
    if (b == 0xF4) hi = 0x8F;  // past U+10FFFF
  } else {
    return 0;
  }
  if (i + n > s.size() || at(i + 1) < lo || at(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (at(i + k) < 0x80 || at(i + k) > 0xBF) return 0;
  }
  return n;
}

// The encoding a byte-order mark or a pattern of zero bytes gives away, "" if none.
std::string otherEncoding(const std::string& s) {
  auto starts = [&](const char* bytes, std::size_t n) {
    return s.size() >= n && std::memcmp(s.data(), bytes, n) == 0;
  };
  if (starts("\x00\x00\xFE\xFF", 4)) return "UTF-32 big-endian (byte-order mark 00 00 FE FF)";
  if (starts("\xFF\xFE\x00\x00", 4)) return "UTF-32 little-endian (byte-order mark FF FE 00 00)";
  if (starts("\xFE\xFF", 2)) return "UTF-16 big-endian (byte-order mark FE FF)";
  if (starts("\xFF\xFE", 2)) return "UTF-16 little-endian (byte-order mark FF FE)";
  if (s.size() >= 4 && s[0] != 0 && s[1] == 0 && s[2] != 0 && s[3] == 0)
    return "UTF-16 little-endian (every other byte is zero)";
  if (s.size() >= 4 && s[0] == 0 && s[1] != 0 && s[2] == 0 && s[3] != 0)
    return "UTF-16 big-endian (every other byte is zero)";
  return "";
}

bool beforeValue(char c) {
  return std::isspace(static_cast<unsigned char>(c)) || (c != 0 && std::strchr("[{,:", c));
}

// Nesting depth and number tokens, checked before nlohmann sees the text.
void checkLimits(const std::string& text, const std::string& where) {
  int depth = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {  // skip the string
      for (++i; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\') ++i;
      }
      continue;
    }
    if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        failAt(where, text, i,
               "nested deeper than " + std::to_string(kMaxJsonDepth) +
                   " levels of [ and {; expected at most " + std::to_string(kMaxJsonDepth));
      }
    } else if (c == ']' || c == '}') {
      depth = depth > 0 ? depth - 1 : 0;
    } else if ((c == '-' || std::isdigit(static_cast<unsigned char>(c))) &&
               (i == 0 || beforeValue(text[i - 1]))) {
      std::size_t end = i;
      while (end < text.size() && text[end] != 0 && std::strchr("+-0123456789.eE", text[end]))
        ++end;
      const std::size_t length = end - i;
      if (length > kMaxNumberChars) {
        failAt(where, text, i,
               "a number of " + readableCount(static_cast<double>(length)) +
                   " characters; expected at most " + std::to_string(kMaxNumberChars) +
                   " (a double keeps 17 significant digits)");
      }
      const std::string token = text.substr(i, length);
      if (!std::isfinite(std::strtod(token.c_str(), nullptr))) {
        failAt(where, text, i,
               "the number " + token +
                   " is out of range; expected a magnitude below 1.8e308 (a double)");
      }
      i = end - 1;
    }
  }
}

// Byte offset of the k-th object key (0-based, in document order) of a text nlohmann has parsed
// at least up to that key.
std::size_t keyOffset(const std::string& text, std::size_t k) {
  std::vector<char> open;
  bool expectKey = false;
  std::size_t count = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      if (expectKey && count++ == k) return i;
      expectKey = false;
      for (++i; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\') ++i;
      }
    } else if (c == '{' || c == '[') {
      open.push_back(c);
      expectKey = c == '{';
    } else if (c == '}' || c == ']') {
      if (!open.empty()) open.pop_back();
      expectKey = false;
    } else if (c == ',') {
      expectKey = !open.empty() && open.back() == '{';
    } else if (!std::isspace(static_cast<unsigned char>(c))) {
      expectKey = false;
    }
  }
  return 0;
}

struct DuplicateKey {
  std::string path;
  std::size_t key = 0, first = 0;  // document-order indices of the two keys
};

// nlohmann's parser callback keeping the path to the current value and each object's keys.
class DuplicateFinder {
 public:
  bool operator()(int, json::parse_event_t event, json& parsed) {
    using E = json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        countElement();
        frames_.push_back(Frame{event == E::object_start, {}, "", -1});
        break;
      case E::object_end:
      case E::array_end:
        if (!frames_.empty()) frames_.pop_back();
        break;
      case E::key: {
        Frame& f = frames_.back();
        const std::string key = parsed.get<std::string>();
        const auto [it, fresh] = f.keys.emplace(key, keys_);
        if (!fresh) throw DuplicateKey{pathTo(key), keys_, it->second};
        f.key = key;
        ++keys_;
        break;
      }
      case E::value:
        countElement();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool object = false;
    std::map<std::string, std::size_t> keys;  // key -> its document-order index
    std::string key;                          // the key being read (objects)
    long long index = -1;                     // the element being read (arrays)
  };
  void countElement() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }
  std::string pathTo(const std::string& key) const {
    std::string path;
    for (std::size_t f = 0; f + 1 < frames_.size(); ++f) {
      if (frames_[f].object)
        path += (path.empty() ? "" : ".") + printable(frames_[f].key);
      else
        path += "[" + std::to_string(frames_[f].index) + "]";
    }
    return path + (path.empty() ? "" : ".") + printable(key);
  }
  std::vector<Frame> frames_;
  std::size_t keys_ = 0;
};

// nlohmann's message from "syntax error" on, with what it quotes made printable and short.
std::string syntaxMessage(const std::string& what) {
  const std::size_t start = what.find("syntax error");
  std::string message = start == std::string::npos ? what : what.substr(start);
  const std::string marker = "last read: '";
  const std::size_t quote = message.find(marker);
  if (quote != std::string::npos) {
    const std::size_t from = quote + marker.size();
    const std::size_t to = message.rfind('\'');
    const std::string read =
        to > from ? message.substr(from, to - from) : message.substr(from, std::string::npos);
    message = message.substr(0, from) + printable(read) + "'";
  }
  return printable(message, 200);
}

std::optional<json> parse(const std::string& text, const std::string& where, bool mustBeJson) {
  requireUtf8(text, where);
  // nlohmann's reader takes a NUL byte for the end of the text and would drop what follows.
  const std::size_t nul = text.find('\0');
  if (nul != std::string::npos) {
    failAt(where, text, nul,
           "a NUL byte (at byte " + std::to_string(nul) + "); expected JSON text, which has none");
  }
  checkLimits(text, where);
  DuplicateFinder finder;
  try {
    json doc = json::parse(text, std::ref(finder), mustBeJson);
    if (doc.is_discarded()) return std::nullopt;
    return doc;
  } catch (const DuplicateKey& d) {
    const std::string first = lineColumn(text, keyOffset(text, d.first));
    failAt(where, text, keyOffset(text, d.key),
           "duplicate key " + d.path + " (first given at " + first +
               "); expected each key once (JSON keeps only one of the two)");
  } catch (const json::parse_error& e) {
    failAt(where, text, e.byte > 0 ? e.byte - 1 : 0, "invalid JSON: " + syntaxMessage(e.what()));
  } catch (const json::exception& e) {
    throw InputError(where + ": invalid JSON: " + printable(e.what(), 200));
  }
}

}  // namespace

std::string lineColumn(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n')
      ++line, column = 1;
    else
      ++column;
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

void requireUtf8(const std::string& text, const std::string& where) {
  const std::string other = otherEncoding(text);
  if (!other.empty())
    throw InputError(where + ": not UTF-8 text: it looks like " + other + "; save it as UTF-8");
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8Length(text, i);
    if (n == 0) {
      char byte[8];
      std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(text[i]));
      failAt(where, text, i,
             std::string("not UTF-8 text (byte ") + byte +
                 " does not belong to a UTF-8 character); save it as UTF-8");
    }
    i += n;
  }
}

json parseJson(const std::string& text, const std::string& where) {
  return *parse(text, where, true);
}

std::optional<json> parseJsonIfJson(const std::string& text, const std::string& where) {
  return parse(text, where, false);
}

}  // namespace sph::io::scene
