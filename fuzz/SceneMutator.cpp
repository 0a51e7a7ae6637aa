#include "fuzz/SceneMutator.h"

#include <cstdint>
#include <functional>
#include <stdexcept>

namespace sph::fuzz {
namespace {

using Node = std::shared_ptr<JsonValue>;

// A reader for the shipped scenes (valid JSON, no escapes beyond the simple ones).
class Reader {
 public:
  explicit Reader(const std::string& t) : t_(t) {}
  Node value() {
    space();
    auto v = std::make_shared<JsonValue>();
    const char c = at_ < t_.size() ? t_[at_] : '\0';
    if (c == '{') {
      v->kind = JsonValue::Kind::Object;
      ++at_;
      for (space(); peek() != '}'; space()) {
        v->keys.push_back(string());
        space();
        expect(':');
        v->items.push_back(value());
        space();
        if (peek() == ',') ++at_;
      }
      ++at_;
    } else if (c == '[') {
      v->kind = JsonValue::Kind::Array;
      ++at_;
      for (space(); peek() != ']'; space()) {
        v->items.push_back(value());
        space();
        if (peek() == ',') ++at_;
      }
      ++at_;
    } else if (c == '"') {
      v->kind = JsonValue::Kind::String;
      v->text = string();
    } else if (t_.compare(at_, 4, "null") == 0) {
      at_ += 4;
    } else if (t_.compare(at_, 4, "true") == 0 || t_.compare(at_, 5, "false") == 0) {
      v->kind = JsonValue::Kind::Bool;
      v->text = t_[at_] == 't' ? "true" : "false";
      at_ += v->text.size();
    } else {
      v->kind = JsonValue::Kind::Number;
      const std::size_t from = at_;
      while (at_ < t_.size() && std::string("+-0123456789.eE").find(t_[at_]) != std::string::npos)
        ++at_;
      if (at_ == from) throw std::runtime_error("not JSON at byte " + std::to_string(at_));
      v->text = t_.substr(from, at_ - from);
    }
    return v;
  }

 private:
  char peek() const {
    if (at_ >= t_.size()) throw std::runtime_error("JSON ends early");
    return t_[at_];
  }
  void space() {
    while (at_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[at_]))) ++at_;
  }
  void expect(char c) {
    if (peek() != c) throw std::runtime_error(std::string("expected ") + c);
    ++at_;
  }
  std::string string() {
    expect('"');
    std::string s;
    while (peek() != '"') {
      if (t_[at_] == '\\') s += t_[at_++];
      s += t_[at_++];
    }
    ++at_;
    return s;  // escapes kept as written
  }
  const std::string& t_;
  std::size_t at_ = 0;
};

std::string write(const JsonValue& v) {
  switch (v.kind) {
    case JsonValue::Kind::Null:
      return "null";
    case JsonValue::Kind::Bool:
    case JsonValue::Kind::Number:
      return v.text;
    case JsonValue::Kind::String:
      return "\"" + v.text + "\"";
    case JsonValue::Kind::Array: {
      std::string s = "[";
      for (std::size_t i = 0; i < v.items.size(); ++i) s += (i ? ", " : "") + write(*v.items[i]);
      return s + "]";
    }
    case JsonValue::Kind::Object: {
      std::string s = "{";
      for (std::size_t i = 0; i < v.items.size(); ++i)
        s += (i ? ",\n" : "\n") + std::string("\"") + v.keys[i] + "\": " + write(*v.items[i]);
      return s + "\n}";
    }
  }
  return "";
}

Node deepCopy(const Node& n) {
  auto c = std::make_shared<JsonValue>(*n);
  for (Node& item : c->items) item = deepCopy(item);
  return c;
}

// Every value of the tree with the path that names it ("fluids[0].max[1]").
void collect(const Node& n, const std::string& path, std::vector<std::pair<Node, std::string>>& out) {
  out.emplace_back(n, path.empty() ? "the scene" : path);
  for (std::size_t i = 0; i < n->items.size(); ++i) {
    const std::string child = n->kind == JsonValue::Kind::Object
                                  ? (path.empty() ? "" : path + ".") + n->keys[i]
                                  : path + "[" + std::to_string(i) + "]";
    collect(n->items[i], child, out);
  }
}

template <class T>
const T& pick(const std::vector<T>& v, std::mt19937_64& random) {
  return v[random() % v.size()];
}

Node leaf(JsonValue::Kind kind, const std::string& text) {
  auto v = std::make_shared<JsonValue>();
  v->kind = kind;
  v->text = text;
  return v;
}

const std::vector<std::string> kNumbers = {
    "0",     "-0",   "-1",   "1e308", "-1e308", "1e-308", "1e999", "-1e999", "4.9e-324",
    "2147483648", "-2147483649", "18446744073709551616", "123456789012345678901234567890",
    "0.0000001", "1e6", "1e9", "3.5", "-3.5", "00", "1.", ".5", "1e", "+1", "0x10", "NaN",
    "Infinity"};

const std::vector<std::string> kStrings = {
    "", " ", "point", "quad", "both", "dfsph", "wcsph", "exact", "cdt", "\\u0000", "\\ud800",
    "\\u00e9t\\u00e9", "caf\xc3\xa9", "\xff\xfe", "a\\nb", "\\\\", "%s%s%n", "../../etc/passwd",
    std::string(300, 'x'), "\x1b[31mred"};

}  // namespace

SceneMutator::SceneMutator(const std::string& text) : text_(text) {
  Reader r(text_);
  root_ = r.value();
}

std::string SceneMutator::mutate(std::mt19937_64& random, std::string& what) const {
  const unsigned kind = random() % 20;
  if (kind >= 16) {
    // The text itself.
    std::string t = text_;
    const std::size_t at = t.empty() ? 0 : random() % t.size();
    switch (kind) {
      case 16: {
        const char bytes[] = {'\0', '\x01', '\x1b', '\x7f', '\t', '\r', '\f'};
        t.insert(at, 1, bytes[random() % sizeof bytes]);
        what = "a control byte at " + std::to_string(at);
        break;
      }
      case 17: {
        const char* bad[] = {"\xff", "\xc0\x80", "\xed\xa0\x80", "\xe2\x82", "\xf4\x90\x80\x80"};
        t.insert(at, bad[random() % 5]);
        what = "invalid UTF-8 at " + std::to_string(at);
        break;
      }
      case 18:
        if (random() % 2) {
          t = "\xef\xbb\xbf" + t;
          what = "a UTF-8 byte-order mark";
        } else {
          std::string wide = "\xff\xfe";
          for (char c : t) wide += c, wide += '\0';
          t = wide;
          what = "UTF-16";
        }
        break;
      default:
        t.resize(at);
        what = "cut at byte " + std::to_string(at);
        break;
    }
    return t;
  }
  const Node root = deepCopy(root_);
  std::vector<std::pair<Node, std::string>> values;
  collect(root, "", values);
  const auto& [node, path] = pick(values, random);
  JsonValue& v = *node;
  switch (kind) {
    case 0:
    case 1:
    case 2:  // a number, of any value
      v = *leaf(JsonValue::Kind::Number, pick(kNumbers, random));
      what = path + " = " + v.text;
      break;
    case 3:  // a string
      v = *leaf(JsonValue::Kind::String, pick(kStrings, random));
      what = path + " = a string";
      break;
    case 4:  // another kind of value
      v = random() % 3 == 0   ? *leaf(JsonValue::Kind::Null, "")
          : random() % 2 == 0 ? *leaf(JsonValue::Kind::Bool, "true")
                              : JsonValue{JsonValue::Kind::Object, "", {}, {}};
      what = path + " = another kind of value";
      break;
    case 5:
    case 6:  // a key of an object renamed, dropped or doubled
      if (v.kind == JsonValue::Kind::Object && !v.keys.empty()) {
        const std::size_t i = random() % v.keys.size();
        const unsigned how = random() % 4;
        if (how == 0) {
          v.keys[i] = v.keys[i].substr(0, v.keys[i].size() - 1);
          what = path + ": key " + v.keys[i] + " cut short";
        } else if (how == 1) {
          what = path + ": key " + v.keys[i] + " dropped";
          v.keys.erase(v.keys.begin() + static_cast<std::ptrdiff_t>(i));
          v.items.erase(v.items.begin() + static_cast<std::ptrdiff_t>(i));
        } else if (how == 2) {
          v.keys.push_back(v.keys[i]);
          v.items.push_back(deepCopy(v.items[i]));
          what = path + ": key " + v.keys[i] + " twice";
        } else {
          v.keys.push_back(random() % 2 ? "unknown_key" : "");
          v.items.push_back(leaf(JsonValue::Kind::Number, "1"));
          what = path + ": key '" + v.keys.back() + "' added";
        }
      } else {
        what = path + " (no object: unchanged)";
      }
      break;
    case 7:
    case 8:  // a list emptied, cut, or its first element repeated
      if (v.kind == JsonValue::Kind::Array) {
        const unsigned how = random() % 3;
        if (how == 0 || v.items.empty()) {
          v.items.clear();
          what = path + " = []";
        } else if (how == 1) {
          v.items.pop_back();
          what = path + " one element short";
        } else {
          const std::size_t n = random() % 2 ? 1 : 2000;
          for (std::size_t i = 0; i < n; ++i) v.items.push_back(deepCopy(v.items[0]));
          what = path + " with " + std::to_string(n) + " more elements";
        }
      } else {
        v = JsonValue{JsonValue::Kind::Array, "", {}, {deepCopy(node)}};
        what = path + " in a list";
      }
      break;
    case 9: {  // nesting: the value buried under brackets
      const std::size_t depth = random() % 2 ? 64 : 100000;
      // Written as text: a tree this deep would take the stack of whatever walks it.
      const std::string value = write(v), marker = "\"@@nested@@\"";
      v = *leaf(JsonValue::Kind::String, "@@nested@@");
      std::string text = write(*root);
      const std::size_t at = text.find(marker);
      text.replace(at, marker.size(), std::string(depth, '[') + value + std::string(depth, ']'));
      what = path + " under " + std::to_string(depth) + " brackets";
      return text;
    }
    default: {  // a number nudged to an edge: zero, negative, tiny, huge
      if (v.kind == JsonValue::Kind::Number) {
        const char* nudges[] = {"0", "-", "1e-30*", "1e30*", "1e6*"};
        const std::string n = nudges[random() % 5];
        if (n == "-")
          v.text = v.text[0] == '-' ? v.text.substr(1) : "-" + v.text;
        else if (n == "0")
          v.text = "0";
        else
          v.text = std::to_string(std::stod(n.substr(0, n.size() - 1)) * std::stod(v.text));
        what = path + " = " + v.text;
      } else {
        what = path + " (no number: unchanged)";
      }
      break;
    }
  }
  return write(*root);
}

}  // namespace sph::fuzz
