#version 450 core
// One rain streak per instance (render/rain/RainRenderer.h): a camera-facing quad from where the
// drop was one exposure ago to where it is, u_width wide; the spotlight weight per drop (the
// paper colours each particle, eq. (13)).
#include "rain_spotlight.glsl"

layout(location = 0) in vec4 a_drop;  // xyz: position (m), w: streak image layer

uniform mat4 u_projView;
uniform vec3 u_eye;
uniform vec3 u_right;     // camera right, for a streak seen end-on
uniform vec3 u_velocity;  // m/s
uniform float u_exposure;  // s
uniform float u_width;     // m

out vec2 v_uv;
flat out float v_layer;
flat out float v_light;

void main() {
  vec3 head = a_drop.xyz;
  vec3 tail = head - u_velocity * u_exposure;
  vec3 toEye = u_eye - 0.5 * (head + tail);
  vec3 side = cross(head - tail, toEye);
  side = length(side) > 1e-12 ? normalize(side) : u_right;
  // Triangle strip: (tail, -), (head, -), (tail, +), (head, +).
  float along = float(gl_VertexID & 1);
  float across = float(gl_VertexID >> 1) * 2.0 - 1.0;
  vec3 p = mix(tail, head, along) + across * 0.5 * u_width * side;
  v_uv = vec2(0.5 + 0.5 * across, along);
  v_layer = a_drop.w;
  v_light = spotlightWeight(head);
  gl_Position = u_projView * vec4(p, 1.0);
}
