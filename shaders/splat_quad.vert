#version 450 core
// Quadrangular-pyramid splats (seed 003, sections 4-5): the vertices were placed on the CPU by
// eq. (6) (render/splat/SplatBuilder.cpp), each with its own SPH normal; lighting is evaluated here, per
// vertex, and interpolated across the 4 triangles (Gouraud shading).
#include "splat_shading.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;  // outward unit

uniform mat4 u_projView;
uniform vec3 u_eye;
// Translucent water (render.alpha < 1) shows its back surface through its front one; there the eye
// is inside the water, so the side it sees is the one whose normal points away (-n). Lit with n
// those splats read as grazing (Fresnel 1: pure sky), the white shards on thin jets.
uniform int u_twoSided;

out vec3 v_colour;
out vec3 v_normal;
#ifdef SPH_GBUFFER
out vec3 v_position;  // the deferred pipeline's G-buffer (splat.frag)
#endif

void main() {
  vec3 toEye = normalize(u_eye - a_position);
  vec3 n = (u_twoSided != 0 && dot(a_normal, toEye) < 0.0) ? -a_normal : a_normal;
  v_colour = shadeSurfaceAt(a_position, n, toEye);
  v_normal = a_normal;
#ifdef SPH_GBUFFER
  v_position = a_position;
#endif
  gl_Position = u_projView * vec4(a_position, 1.0);
}
