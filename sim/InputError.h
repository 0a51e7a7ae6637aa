// Bad input from the user (a scene, a cache, a flag, a scene too big for the machine): one human
// line naming the file, the key or dataset, and what was expected (STYLE.md rule 10, second kind).
// The CLI prints what() and exits with code 2. It lives in sim/ because the simulator itself
// meets input limits too (a particle count past the id range, say) and says so in these terms.
#pragma once

#include <stdexcept>
#include <string>

namespace sph {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace sph
