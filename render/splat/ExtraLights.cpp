#include "render/splat/ExtraLights.h"

#include "render/splat/Lighting.h"

namespace sph::render::splat {

void applyExtraLights(GLuint program, const Lighting& l) {
  if (l.extra != nullptr) {
    l.extra->apply(program);
    return;
  }
  glProgramUniform1i(program, glGetUniformLocation(program, "u_particleLights"), 0);
}

}  // namespace sph::render::splat
