#include "render/frame/SpotlightUniforms.h"

#include "render/frame/ProgramUniforms.h"

namespace sph::render::frame {

void setSpotlightUniforms(GLuint p, const std::optional<scene::SpotlightDesc>& light) {
  glProgramUniform1i(p, glGetUniformLocation(p, "u_spotOn"), light ? 1 : 0);
  if (!light) return;
  setVec3(p, "u_spotPosition", light->position);
  setVec3(p, "u_spotDirection", light->direction);
  setFloat(p, "u_spotHeight", light->height);
  setFloat(p, "u_spotBaseRadius", light->baseRadius);
  setVec3(p, "u_spotColour", light->colour);
  setFloat(p, "u_spotIntensity", light->intensity);
  setFloat(p, "u_spotSoftEdge", light->softEdge);
  glProgramUniform1i(p, glGetUniformLocation(p, "u_spotFalloff"), light->falloff ? 1 : 0);
}

}  // namespace sph::render::frame
