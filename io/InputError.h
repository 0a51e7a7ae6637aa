// Bad input from the user (a scene, a cache, a flag): one human line naming the file, the key or
// dataset, and what was expected (STYLE.md rule 10, second kind). The CLI prints what() and exits
// with code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace sph::io {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace sph::io
