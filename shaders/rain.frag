#version 450 core
// A rain streak's colour (seed 002 eq. (13)): texture x light colour x intensity inside the
// spotlight's cone, texture x the unlit tint outside; alpha from the streak image. Written
// sRGB-encoded like the splats and solids.
#include "rain_spotlight.glsl"

in vec2 v_uv;
flat in float v_layer;
flat in float v_light;

uniform sampler2DArray u_streaks;
uniform vec3 u_unlit;  // linear RGB

layout(location = 0) out vec4 o_colour;

vec3 toSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  float texel = texture(u_streaks, vec3(v_uv, v_layer)).r;
  vec3 lit = u_spotColour * u_spotIntensity;
  vec3 colour = mix(u_unlit, lit, v_light);
  o_colour = vec4(toSrgb(colour), texel);
}
