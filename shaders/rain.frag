#version 450 core
// A rain streak's fragment (seed 002 eq. (13)): the drop's colour (lit or not, sRGB-encoded in
// rain.vert) with the streak image's alpha. Kept to one texture fetch: llvmpipe shades every
// fragment of every streak on the CPU.
in vec3 v_uvLayer;
flat in vec3 v_colour;

uniform sampler2DArray u_streaks;

layout(location = 0) out vec4 o_colour;

void main() { o_colour = vec4(v_colour, texture(u_streaks, v_uvLayer).r); }
