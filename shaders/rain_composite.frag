#version 450 core
// The CPU-rasterised streaks of one pixel (render/rain/StreakRaster.h): rgb the streaks' colour
// already multiplied by their alpha, a what is left of the frame behind them. Blended with
// GL_ONE, GL_SRC_ALPHA: frame = rgb + a frame, drop order kept as the triangles kept it.
uniform sampler2D u_layer;
uniform ivec2 u_origin;  // the viewport's lower left corner, pixels

layout(location = 0) out vec4 o_colour;

void main() { o_colour = texelFetch(u_layer, ivec2(gl_FragCoord.xy) - u_origin, 0); }
