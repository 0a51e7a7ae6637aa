// Where GLSL sources come from (STYLE.md rule 11): shaders/ is embedded in the binary at build
// time (render/gl/EmbedShaders.cmake), so `sphsplat` runs from any directory; with the environment
// variable SPHSPLAT_SHADER_DIR set, the files are read from that directory at run time instead
// (edit a shader, rerun, no rebuild). Names are file names under shaders/ ("cdt_collide.vert").
#pragma once

#include <string>
#include <vector>

namespace sph::render::gl {

// One GLSL file: `name` is what messages call it ("shaders/cdt_collide.vert" or a full path).
struct ShaderSource {
  std::string name;
  std::string text;
};

namespace detail {
struct EmbeddedShader {
  const char* name;
  const char* text;
};
const std::vector<EmbeddedShader>& embeddedShaders();
}  // namespace detail

class ShaderLibrary {
 public:
  // The copy embedded at build time.
  static ShaderLibrary embedded();
  // Files read from `directory` when loaded.
  static ShaderLibrary directory(std::string directory);
  // SPHSPLAT_SHADER_DIR if it is set, else the embedded copy.
  static ShaderLibrary fromEnvironment();

  // Throws ShaderError if there is no such shader.
  ShaderSource load(const std::string& name) const;

 private:
  std::string directory_;
};

}  // namespace sph::render::gl
