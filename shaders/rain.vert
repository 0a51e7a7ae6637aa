#version 450 core
// One rain streak per four vertices (render/rain/RainRenderer.h): a camera-facing quad from where the
// drop was one exposure ago to where it is, u_width wide. Everything that is the same over the
// streak is done here, once per vertex, not per fragment: the spotlight weight per drop (the
// paper colours each particle, eq. (13)) and the colour's sRGB encoding.
#include "rain_spotlight.glsl"

// Per drop xyz: position (m), w: streak image layer. Pulled by index rather than instanced:
// llvmpipe runs an instanced draw as one small draw per instance.
layout(std430, binding = 0) readonly buffer Drops { vec4 drops[]; };

uniform mat4 u_projView;
uniform vec3 u_eye;
uniform vec3 u_right;     // camera right, for a streak seen end-on
uniform vec3 u_velocity;  // m/s
uniform float u_exposure;  // s
uniform float u_width;     // m
uniform vec3 u_unlit;      // linear RGB

out vec3 v_uvLayer;  // streak image coordinates and layer
flat out vec3 v_colour;  // sRGB-encoded

vec3 toSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  vec4 drop = drops[gl_VertexID >> 2];
  int corner = gl_VertexID & 3;
  vec3 head = drop.xyz;
  vec3 tail = head - u_velocity * u_exposure;
  vec3 toEye = u_eye - 0.5 * (head + tail);
  vec3 side = cross(head - tail, toEye);
  side = length(side) > 1e-12 ? normalize(side) : u_right;
  // Corners 0..3: (tail, -), (head, -), (tail, +), (head, +); the index buffer makes two
  // triangles of them.
  float along = float(corner & 1);
  float across = float(corner >> 1) * 2.0 - 1.0;
  vec3 p = mix(tail, head, along) + across * 0.5 * u_width * side;
  v_uvLayer = vec3(0.5 + 0.5 * across, along, drop.w);
  // eq. (13): texture x light colour x intensity inside the cone, the unlit tint outside.
  v_colour = toSrgb(mix(u_unlit, u_spotColour * u_spotIntensity, spotlightWeight(head)));
  gl_Position = u_projView * vec4(p, 1.0);
}
