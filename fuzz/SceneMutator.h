// Damaged copies of a scene file for the scene fuzzer (fuzz/fuzz_scene.cpp), grammar-aware: the
// scene is read into a tree and a key, a value or the nesting is changed (a key renamed, dropped
// or doubled, a number made huge, negative, not a number or text, a list emptied or repeated, a
// value buried under thousands of brackets), or the text itself (a NUL or control byte, invalid
// UTF-8, a byte-order mark, UTF-16, a cut).
#pragma once

#include <memory>
#include <random>
#include <string>
#include <vector>

namespace sph::fuzz {

// A JSON value as the fuzzer handles it: numbers keep their text, objects their key order.
struct JsonValue {
  enum class Kind { Null, Bool, Number, String, Array, Object } kind = Kind::Null;
  std::string text;  // a number's or string's text (the string without its quotes), a bool's
  std::vector<std::string> keys;
  std::vector<std::shared_ptr<JsonValue>> items;  // an array's elements or an object's values
};

class SceneMutator {
 public:
  // `text` must be valid JSON (a shipped scene).
  explicit SceneMutator(const std::string& text);

  // A damaged copy, and a few words on what was changed.
  std::string mutate(std::mt19937_64& random, std::string& what) const;

 private:
  std::shared_ptr<JsonValue> root_;
  std::string text_;
};

}  // namespace sph::fuzz
