#include "render/frame/LightingUniforms.h"

#include "render/frame/ExtraLights.h"
#include "render/frame/ProgramUniforms.h"
#include "render/frame/SpotlightUniforms.h"

namespace sph::render::frame {

void setLightingUniforms(GLuint p, const Lighting& l) {
  setVec3(p, "u_toLight", l.toLight.normalized());
  setVec3(p, "u_base", l.base);
  setFloat(p, "u_ambient", l.ambient);
  setFloat(p, "u_diffuse", l.diffuse);
  setFloat(p, "u_specular", l.specular);
  setFloat(p, "u_shininess", l.shininess);
  setInt(p, "u_environment", l.environment ? 1 : 0);
  setVec3(p, "u_horizon", l.horizon);
  setVec3(p, "u_zenith", l.zenith);
  setFloat(p, "u_fresnelMin", l.fresnelMin);
  applyExtraLights(p, l);
  setSpotlightUniforms(p, l.spotlight);
}

}  // namespace sph::render::frame
