// The uniforms of the one lighting model (Lighting.h) for any program that shades with it
// (shaders/splat_shading.glsl through the splats' and the solids' shaders): the scene's light, the
// surface's material, the sky's reflection, the particle lights and the rain's spotlight. A
// renderer passes the Lighting its surface is lit with (the solids their own material, no sky)
// and sets what only it uses after.
#pragma once

#include <glad/gl.h>

#include "render/frame/Lighting.h"

namespace sph::render::frame {

void setLightingUniforms(GLuint program, const Lighting& lighting);

}  // namespace sph::render::frame
