#include "io/scene/JsonReader.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "io/MessageText.h"

namespace sph::io::scene {
namespace {

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace

bool positive(double v) {
  return v > 0;
}
bool nonNegative(double v) {
  return v >= 0;
}

std::string describeJson(const nlohmann::json& v) {
  // ASCII only (\uXXXX escapes) and at most 40 characters, whatever the value holds.
  const std::string text =
      printable(v.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace), 40);
  switch (v.type()) {
    case nlohmann::json::value_t::string:
      return "the string " + text;
    case nlohmann::json::value_t::boolean:
      return "the boolean " + text;
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::array:
      return "the array " + text;
    case nlohmann::json::value_t::object:
      return "an object";
    default:
      return text;
  }
}

JsonReader::JsonReader(const nlohmann::json& value, std::string path, std::string file)
    : value_(&value), path_(std::move(path)), file_(std::move(file)) {
  if (!value_->is_object()) {
    throw InputError(file_ + ": " + (path_.empty() ? "the scene" : path_) +
                     ": expected an object {...}, got " + describeJson(*value_));
  }
}

std::string JsonReader::keyPath(const std::string& key) const {
  return path_.empty() ? printable(key) : path_ + "." + printable(key);
}

void JsonReader::fail(const std::string& key, const std::string& message) const {
  throw InputError(file_ + ": " + keyPath(key) + ": " + message);
}

bool JsonReader::has(const std::string& key) const {
  return value_->contains(key);
}

double JsonReader::number(const std::string& key, std::optional<double> def, const char* expected,
                          bool (*valid)(double)) {
  used_.insert(key);
  if (!has(key)) {
    if (!def) fail(key, std::string("missing; expected ") + expected);
    return *def;
  }
  const nlohmann::json& v = (*value_)[key];
  if (!v.is_number() || !std::isfinite(v.get<double>()) || (valid && !valid(v.get<double>()))) {
    fail(key, std::string("expected ") + expected + ", got " + describeJson(v));
  }
  if (std::fabs(v.get<double>()) > kMaxSceneNumber) {
    fail(key, std::string("expected ") + expected + " of magnitude at most " +
                  readableNumber(kMaxSceneNumber) + ", got " + describeJson(v));
  }
  return v.get<double>();
}

std::string JsonReader::string(const std::string& key, std::optional<std::string> def,
                               const std::vector<std::string>& allowed) {
  used_.insert(key);
  std::string choices;
  for (const std::string& a : allowed) choices += (choices.empty() ? "\"" : ", \"") + a + "\"";
  const std::string expected = allowed.empty() ? "a string" : "one of " + choices;
  if (!has(key)) {
    if (!def) fail(key, "missing; expected " + expected);
    return *def;
  }
  const nlohmann::json& v = (*value_)[key];
  if (!v.is_string()) fail(key, "expected " + expected + ", got " + describeJson(v));
  const std::string s = v.get<std::string>();
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
    fail(key, "expected " + expected + ", got " + describeJson(v));
  }
  return s;
}

bool JsonReader::boolean(const std::string& key, std::optional<bool> def) {
  used_.insert(key);
  if (!has(key)) {
    if (!def) fail(key, "missing; expected true or false");
    return *def;
  }
  const nlohmann::json& v = (*value_)[key];
  if (!v.is_boolean()) fail(key, "expected true or false, got " + describeJson(v));
  return v.get<bool>();
}

Vec3 JsonReader::vec3(const std::string& key, std::optional<Vec3> def, const char* expected) {
  used_.insert(key);
  if (!has(key)) {
    if (!def) fail(key, std::string("missing; expected ") + expected + " [x, y, z]");
    return *def;
  }
  const nlohmann::json& v = (*value_)[key];
  bool ok = v.is_array() && v.size() == 3;
  for (std::size_t i = 0; ok && i < 3; ++i)
    ok = v[i].is_number() && std::isfinite(v[i].get<double>());
  if (!ok) fail(key, std::string("expected ") + expected + " [x, y, z], got " + describeJson(v));
  for (std::size_t i = 0; i < 3; ++i) {
    if (std::fabs(v[i].get<double>()) > kMaxSceneCoordinate) {
      fail(key, std::string("expected ") + expected + " [x, y, z], each between -" +
                    readableNumber(kMaxSceneCoordinate) + " and " +
                    readableNumber(kMaxSceneCoordinate) + ", got " + describeJson(v));
    }
  }
  return Vec3(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
}

std::vector<std::string> JsonReader::stringArray(const std::string& key,
                                                 std::optional<std::vector<std::string>> def,
                                                 const char* expected) {
  used_.insert(key);
  if (!has(key)) {
    if (!def) fail(key, std::string("missing; expected ") + expected);
    return *def;
  }
  const nlohmann::json& v = (*value_)[key];
  bool ok = v.is_array() && !v.empty();
  for (std::size_t i = 0; ok && i < v.size(); ++i) ok = v[i].is_string();
  if (!ok) fail(key, std::string("expected ") + expected + ", got " + describeJson(v));
  return v.get<std::vector<std::string>>();
}

JsonReader JsonReader::object(const std::string& key) {
  used_.insert(key);
  if (!has(key)) fail(key, "missing; expected an object {...}");
  return JsonReader((*value_)[key], keyPath(key), file_);
}

std::optional<JsonReader> JsonReader::optionalObject(const std::string& key) {
  if (!has(key)) {
    used_.insert(key);
    return std::nullopt;
  }
  return object(key);
}

std::vector<JsonReader> JsonReader::objectArray(const std::string& key) {
  used_.insert(key);
  std::vector<JsonReader> out;
  if (!has(key)) return out;
  const nlohmann::json& v = (*value_)[key];
  if (!v.is_array()) fail(key, "expected an array [ {...}, ... ], got " + describeJson(v));
  for (std::size_t i = 0; i < v.size(); ++i) {
    out.emplace_back(v[i], keyPath(key) + "[" + std::to_string(i) + "]", file_);
  }
  return out;
}

void JsonReader::finish() const {
  for (auto it = value_->begin(); it != value_->end(); ++it) {
    if (used_.count(it.key())) continue;
    std::string best;
    std::size_t bestDistance = 3;  // suggest only near misses
    for (const std::string& known : used_) {
      if (it.key().size() > known.size() + bestDistance) continue;  // no near miss; and cheap
      const std::size_t d = editDistance(it.key(), known);
      if (d < bestDistance) best = known, bestDistance = d;
    }
    std::string known;
    for (const std::string& k : used_) known += (known.empty() ? "" : ", ") + k;
    fail(it.key(), "unknown key" + (best.empty() ? "" : " (did you mean \"" + best + "\"?)") +
                       "; known keys here: " + known);
  }
}

}  // namespace sph::io::scene
