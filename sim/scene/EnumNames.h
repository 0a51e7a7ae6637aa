// One name table per user-visible choice (STYLE.md rule 8: methods are chosen by name). Next to
// each such enum, in its own header, stands one function
//
//   constexpr const char* nameOf(CollisionMethod m) {
//     switch (m) {
//       case CollisionMethod::None: return "none";
//       ...
//     }
//     return nullptr;  // not an enumerator
//   }
//
// with no `default:`, so -Wswitch (in -Wall, an error with -Werror) stops the build when an
// enumerator is added without a name. Everything else is derived from it here, found by
// argument-dependent lookup: the scene loader's parsing and its "expected one of ..." messages,
// the CLI's choices and help texts, what the cache records and what `run -v` prints.
// tests/test_enum_names.cpp checks every table: unique names, parseEnum(enumName(e)) == e.
//
// The enums are dense from 0 (the default for an enum class), which is how enumerators<E>() walks
// them.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sph::scene {

// Every enumerator of E, in declaration order.
template <class E>
std::vector<E> enumerators() {
  std::vector<E> all;
  for (int i = 0; nameOf(static_cast<E>(i)) != nullptr; ++i) all.push_back(static_cast<E>(i));
  return all;
}

// The name of an enumerator as scenes and the command line spell it.
template <class E>
const char* enumName(E value) {
  const char* name = nameOf(value);
  return name ? name : "?";  // only for a value that is no enumerator (a cast gone wrong)
}

// The enumerator called `name`, if any.
template <class E>
std::optional<E> parseEnum(std::string_view name) {
  for (E value : enumerators<E>()) {
    if (name == nameOf(value)) return value;
  }
  return std::nullopt;
}

// Every name, in declaration order (what a parser accepts).
template <class E>
std::vector<std::string> enumNames() {
  std::vector<std::string> names;
  for (E value : enumerators<E>()) names.emplace_back(nameOf(value));
  return names;
}

// The names as a phrase for help texts: "point, quad or both".
template <class E>
std::string enumNameList() {
  const std::vector<std::string> names = enumNames<E>();
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

}  // namespace sph::scene
