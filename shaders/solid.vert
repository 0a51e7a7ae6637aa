#version 450 core
// The scene's solids (render/solids/SolidRenderer.h): world position and normal to the fragment
// shader, which lights each pixel.
layout(location = 0) in vec3 a_position;  // m
layout(location = 1) in vec3 a_normal;    // unit, out of the solid

uniform mat4 u_projView;

out vec3 v_position;
out vec3 v_normal;

void main() {
  v_position = a_position;
  v_normal = a_normal;
  gl_Position = u_projView * vec4(a_position, 1.0);
}
