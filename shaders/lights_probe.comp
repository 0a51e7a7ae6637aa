#version 450 core
// The shading's particle-light term (extra_lights.glsl, the same code the solids and the splats
// run) at given points, for the error figures against the exact sum (render/lights/
// LightProbe.cpp): each point's position, normal, direction to the eye in, its light out.
#include "extra_lights.glsl"

layout(local_size_x = 64) in;

struct ProbePoint {
  vec4 position;
  vec4 normal;
  vec4 toEye;
};
layout(std430, binding = 0) readonly buffer Points { ProbePoint points[]; };
layout(std430, binding = 1) writeonly buffer Result { vec4 result[]; };
uniform uint u_count;
uniform vec3 u_probeBase;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  ProbePoint p = points[i];
  result[i] = vec4(extraLight(u_probeBase, p.position.xyz, p.normal.xyz, p.toEye.xyz), 1.0);
}
