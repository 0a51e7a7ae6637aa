#version 450 core
// Point splats (the baseline of seed 003's comparison): one camera-facing square per surface
// particle, drawn as an instanced 4-vertex strip; the particle's one normal lights the whole
// square (flat shading).
#include "splat_shading.glsl"

layout(location = 0) in vec3 a_centre;  // per instance (render/splat/SplatBuilder.h, SplatVertex)
layout(location = 1) in vec3 a_normal;  // outward unit

uniform mat4 u_projView;
uniform vec3 u_eye;
// Translucent water (render.alpha < 1) shows its back surface through its front one; there the eye
// is inside the water, so the side it sees is the one whose normal points away (-n). Lit with n
// those splats read as grazing (Fresnel 1: pure sky), the white shards on thin jets.
uniform int u_twoSided;
uniform vec3 u_cameraRight;
uniform vec3 u_cameraUp;
uniform float u_halfSide;  // m, half the side of the square

out vec3 v_colour;
out vec3 v_normal;
#ifdef SPH_GBUFFER
out vec3 v_position;  // the deferred pipeline's G-buffer (splat.frag)
#endif

void main() {
  vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
  vec3 p = a_centre + u_halfSide * (corner.x * u_cameraRight + corner.y * u_cameraUp);
  vec3 toEye = normalize(u_eye - a_centre);
  vec3 n = (u_twoSided != 0 && dot(a_normal, toEye) < 0.0) ? -a_normal : a_normal;
  v_colour = shadeSurfaceAt(a_centre, n, toEye);
  v_normal = a_normal;
#ifdef SPH_GBUFFER
  v_position = a_centre;
#endif
  gl_Position = u_projView * vec4(p, 1.0);
}
