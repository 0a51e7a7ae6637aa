// Every JSON the program reads (scene files, sweep files, --set values, the scene text a cache
// keeps) goes through here, so hostile text gets one short line naming the place, never a crash:
// - the text must be UTF-8 (a UTF-16 or UTF-32 file is named as such, from its byte-order mark or
//   its zero bytes);
// - nesting is limited to kMaxJsonDepth levels of [ and { (nlohmann::json's recursive
//   destructor overflows the stack near 70,000 levels; a scene needs about 5);
// - a number must fit a double and be at most kMaxNumberChars characters long;
// - an object may not give a key twice (JSON parsers keep one of the two silently: a second
//   "solver" section would replace the whole first one). Found by nlohmann's parser callback.
// Errors are InputError "WHERE:LINE:COLUMN: what was wrong", WHERE being a file or "--set KEY".
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace sph::io::scene {

constexpr int kMaxJsonDepth = 64;
constexpr std::size_t kMaxNumberChars = 64;

// Parses `text`; throws InputError for invalid JSON and for every limit above.
nlohmann::json parseJson(const std::string& text, const std::string& where);

// Like parseJson, but text that is simply not JSON gives nullopt (a --set value such as
// name=pour is a string); the encoding, the limits and duplicate keys still throw.
std::optional<nlohmann::json> parseJsonIfJson(const std::string& text, const std::string& where);

// "3:14": line and column (1-based, in bytes) of a byte offset.
std::string lineColumn(const std::string& text, std::size_t offset);

// Throws InputError "WHERE: not UTF-8 text (...)" unless `text` is valid UTF-8 (a UTF-8
// byte-order mark is allowed).
void requireUtf8(const std::string& text, const std::string& where);

}  // namespace sph::io::scene
