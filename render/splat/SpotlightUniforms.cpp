#include "render/splat/SpotlightUniforms.h"

namespace sph::render::splat {

void setSpotlightUniforms(GLuint p, const std::optional<SpotlightDesc>& light) {
  glProgramUniform1i(p, glGetUniformLocation(p, "u_spotOn"), light ? 1 : 0);
  if (!light) return;
  auto vec3 = [&](const char* name, const Vec3& v) {
    glProgramUniform3f(p, glGetUniformLocation(p, name), v.x(), v.y(), v.z());
  };
  auto scalar = [&](const char* name, float v) {
    glProgramUniform1f(p, glGetUniformLocation(p, name), v);
  };
  vec3("u_spotPosition", light->position);
  vec3("u_spotDirection", light->direction);
  scalar("u_spotHeight", light->height);
  scalar("u_spotBaseRadius", light->baseRadius);
  vec3("u_spotColour", light->colour);
  scalar("u_spotIntensity", light->intensity);
  scalar("u_spotSoftEdge", light->softEdge);
  glProgramUniform1i(p, glGetUniformLocation(p, "u_spotFalloff"), light->falloff ? 1 : 0);
}

}  // namespace sph::render::splat
