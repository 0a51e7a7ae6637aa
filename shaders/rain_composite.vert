#version 450 core
// One triangle over the whole viewport (render/rain/RainRenderer.cpp, rain.draw "cpu"): the
// streaks rasterised on the CPU are blended over the frame in one pass.
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
