#version 450 core
// Per-pixel lighting of the solids with the renderers' lighting model (splat_shading.glsl, fed
// the solid material by render/solids/SolidRenderer.cpp), written sRGB-encoded like the splats.
// SPH_GBUFFER (with SPH_NO_PARTICLE_LIGHTS): the deferred pipeline's G-buffer instead, the colour
// lit by all but the particle lights, which shaders/deferred_lighting.frag adds per pixel.
#include "splat_shading.glsl"

in vec3 v_position;
in vec3 v_normal;

uniform vec3 u_eye;

#ifdef SPH_GBUFFER
#include "gbuffer_out.glsl"
#else
layout(location = 0) out vec4 o_colour;

vec3 toSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
#endif

void main() {
  vec3 n = normalize(v_normal);
  vec3 lit = shadeSurfaceAt(v_position, n, normalize(u_eye - v_position));
#ifdef SPH_GBUFFER
  writeGBuffer(lit, u_base, v_position, n, false);
#else
  o_colour = vec4(toSrgb(lit), 1.0);
#endif
}
