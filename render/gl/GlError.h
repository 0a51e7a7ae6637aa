// Environment failures of the OpenGL side (STYLE.md rule 10, second kind): each carries one human
// line saying what failed and where, never a crash. Bugs stay assertions; these are for machines
// without EGL or with too old a driver, and for shaders that do not compile.
#pragma once

#include <stdexcept>
#include <string>

namespace sph::render::gl {

// Base of everything the GL layer reports to the user.
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// No context could be made: no EGL library, no display, no desktop GL, or too low a version.
class GlUnavailable : public GlError {
 public:
  using GlError::GlError;
};

// A shader did not compile or a program did not link. what() starts with "FILE:LINE:" (the
// shader's file under shaders/ and its own line, includes resolved) when the driver names one.
class ShaderError : public GlError {
 public:
  using GlError::GlError;
};

}  // namespace sph::render::gl
