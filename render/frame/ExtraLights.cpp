#include "render/frame/ExtraLights.h"

#include "render/frame/Lighting.h"

namespace sph::render::frame {

void applyExtraLights(GLuint program, const Lighting& l) {
  if (l.extra != nullptr) {
    l.extra->apply(program);
    return;
  }
  glProgramUniform1i(program, glGetUniformLocation(program, "u_particleLights"), 0);
}

}  // namespace sph::render::frame
