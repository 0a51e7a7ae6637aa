#version 450 core
// Writes the interpolated colour (sRGB-encoded, as render/splat/ReferenceRaymarcher.cpp does) and the
// normal with coverage, for the error figures (render/frame/RenderImage.h).
// SPH_GBUFFER (with SPH_NO_PARTICLE_LIGHTS): the deferred pipeline's G-buffer of the opaque water
// instead (shaders/gbuffer_out.glsl): the per-vertex colour without the particle lights, and the
// position and normal at which shaders/deferred_lighting.frag adds them per pixel.
in vec3 v_colour;
in vec3 v_normal;

#ifdef SPH_GBUFFER
in vec3 v_position;
uniform vec3 u_base;
#include "gbuffer_out.glsl"

void main() {
  float len = length(v_normal);
  writeGBuffer(v_colour, u_base, v_position, len > 0.0 ? v_normal / len : vec3(0.0), true);
}
#else
uniform float u_alpha;

layout(location = 0) out vec4 o_colour;
layout(location = 1) out vec4 o_normal;

vec3 toSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  o_colour = vec4(toSrgb(v_colour), u_alpha);
  float len = length(v_normal);
  o_normal = vec4(len > 0.0 ? v_normal / len : vec3(0.0), 1.0);
}
#endif
