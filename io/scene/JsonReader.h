// Reads one JSON object of a scene while remembering where it is ("solver.spacing",
// "boundaries[2].radius") so every error names the file and the key path. Each key read is marked;
// finish() rejects the keys nobody asked for, with a "did you mean" for near misses.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sim/scene/EnumNames.h"
#include "sim/InputError.h"
#include "sim/Types.h"

namespace sph::io::scene {

// Every scene number is refused beyond this magnitude (docs/scene-format.md): past it a float
// loses every digit that matters, and casts to integers or floats would overflow.
constexpr double kMaxSceneNumber = 1e12;
// Every component of a vector key ([x, y, z]: positions, velocities, gravity, directions) lies
// within +-kMaxSceneCoordinate (m, m/s or m/s^2): a float at 1e6 m still resolves 0.06 m.
constexpr double kMaxSceneCoordinate = 1e6;

class JsonReader {
 public:
  JsonReader(const nlohmann::json& value, std::string path, std::string file);

  const std::string& path() const { return path_; }
  const nlohmann::json* raw() const { return value_; }
  bool has(const std::string& key) const;

  // Scalars. `def` empty = required. The constraint text goes into the error ("a positive
  // number (m)").
  double number(const std::string& key, std::optional<double> def, const char* expected,
                bool (*valid)(double) = nullptr);
  std::string string(const std::string& key, std::optional<std::string> def,
                     const std::vector<std::string>& allowed = {});
  // One of the names of the enum E (its nameOf table, sim/scene/EnumNames.h); `def` empty = required.
  template <class E>
  E choice(const std::string& key, std::optional<E> def) {
    const std::string name =
        string(key, def ? std::optional<std::string>(sph::scene::enumName(*def)) : std::nullopt,
               sph::scene::enumNames<E>());
    return *sph::scene::parseEnum<E>(name);
  }
  bool boolean(const std::string& key, std::optional<bool> def);
  Vec3 vec3(const std::string& key, std::optional<Vec3> def, const char* expected = "3 numbers");
  // A non-empty array of strings, e.g. ["x", "y", "z"].
  std::vector<std::string> stringArray(const std::string& key,
                                       std::optional<std::vector<std::string>> def,
                                       const char* expected);

  JsonReader object(const std::string& key);
  std::optional<JsonReader> optionalObject(const std::string& key);
  std::vector<JsonReader> objectArray(const std::string& key);

  // Marks a key as known without reading it (read elsewhere).
  void accept(const std::string& key) { used_.insert(key); }
  // Throws for every key that was not read.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  std::string keyPath(const std::string& key) const;

 private:
  const nlohmann::json* value_;
  std::string path_, file_;
  mutable std::set<std::string> used_;
};

// Short human description of a JSON value's type and content for errors: "the string \"abc\"".
std::string describeJson(const nlohmann::json& v);

// Validators for number().
bool positive(double v);
bool nonNegative(double v);

}  // namespace sph::io::scene
