#version 450 core
// Per-pixel lighting of the solids with the renderers' lighting model (splat_shading.glsl, fed
// the solid material by render/solids/SolidRenderer.cpp), written sRGB-encoded like the splats.
#include "splat_shading.glsl"

in vec3 v_position;
in vec3 v_normal;

uniform vec3 u_eye;

layout(location = 0) out vec4 o_colour;

vec3 toSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  vec3 n = normalize(v_normal);
  o_colour = vec4(toSrgb(shadeSurfaceAt(v_position, n, normalize(u_eye - v_position))), 1.0);
}
