#version 450 core
// The paper's texture write (seed 000, section 3.2: "the fragment shader converts the 3D
// position to a colour code"), used with collision.texture_write = "raster": position and id into
// the RGBA32F layer, the key (depth bits, draw index) into two R32UI images, and the depth for the
// depth test that keeps the nearest. With u_Peel set (layers after the first) a fragment survives
// only if its key comes after the previous layer's key at that texel: depth peeling.
#include "cdt_constants.glsl"

flat in vec4 f_Texel;   // xyz position (m), w id
flat in uvec2 f_Key;    // depth bits, draw index
flat in float f_Depth;  // [0, 1)

layout(binding = CDT_PEEL_DEPTH_UNIT) uniform usampler2D u_PreviousDepth;
layout(binding = CDT_PEEL_INDEX_UNIT) uniform usampler2D u_PreviousIndex;
uniform int u_Peel;

layout(location = 0) out vec4 o_Texel;
layout(location = 1) out uint o_DepthKey;
layout(location = 2) out uint o_IndexKey;

void main() {
  if (u_Peel != 0) {
    ivec2 t = ivec2(gl_FragCoord.xy);
    uint depth = texelFetch(u_PreviousDepth, t, 0).x;
    uint index = texelFetch(u_PreviousIndex, t, 0).x;
    bool after = f_Key.x > depth || (f_Key.x == depth && f_Key.y > index);
    if (!after) discard;
  }
  o_Texel = f_Texel;
  o_DepthKey = f_Key.x;
  o_IndexKey = f_Key.y;
  gl_FragDepth = f_Depth;
}
