// The uniforms of shaders/rain_spotlight.glsl (seed 002's cone spotlight, eq. (10)-(13)) for any
// program that includes it: the water's splats and the solids through extra_lights.glsl's hook,
// and the rain streaks. None: u_spotOn = 0, the shading of a scene without rain.
#pragma once

#include <optional>

#include <glad/gl.h>
#include "sim/scene/RainDesc.h"

namespace sph::render::frame {

void setSpotlightUniforms(GLuint program, const std::optional<scene::SpotlightDesc>& light);

}  // namespace sph::render::frame
