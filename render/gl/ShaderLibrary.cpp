#include "render/gl/ShaderLibrary.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "render/gl/GlError.h"

namespace sph::render::gl {

ShaderLibrary ShaderLibrary::embedded() {
  return ShaderLibrary{};
}

ShaderLibrary ShaderLibrary::directory(std::string directory) {
  ShaderLibrary lib;
  lib.directory_ = std::move(directory);
  if (lib.directory_.empty()) lib.directory_ = ".";
  return lib;
}

ShaderLibrary ShaderLibrary::fromEnvironment() {
  const char* dir = std::getenv("SPHSPLAT_SHADER_DIR");
  return dir && *dir ? directory(dir) : embedded();
}

ShaderSource ShaderLibrary::load(const std::string& name) const {
  if (directory_.empty()) {
    for (const detail::EmbeddedShader& s : detail::embeddedShaders()) {
      if (name == s.name) return {"shaders/" + name, s.text};
    }
    throw ShaderError("shaders/" + name + ": no such shader in this build (embedded from " +
                      SPHSPLAT_SHADER_SOURCE_DIR + ")");
  }
  const std::string path = directory_ + "/" + name;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ShaderError(path + ": cannot open the shader (SPHSPLAT_SHADER_DIR=" + directory_ + ")");
  std::ostringstream text;
  text << in.rdbuf();
  return {path, text.str()};
}

}  // namespace sph::render::gl
