#version 450 core
// The solids' G-buffer (render/lights/LightComparison.cpp): world position and unit normal per
// pixel, alpha 1 where a solid was drawn, for the particle lights' exact reference and error
// figures.
in vec3 v_position;
in vec3 v_normal;

layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;

void main() {
  o_position = vec4(v_position, 1.0);
  o_normal = vec4(normalize(v_normal), 1.0);
}
