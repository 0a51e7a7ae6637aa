#version 450 core
// Draws the positions the collision pass just wrote once more for layers after the first (our
// depth-peeling improvement, failure modes 3 and 4): same texel and key as the collision pass's
// own write, so cdt_write.frag can keep the next-nearest particle per texel.
#include "cdt_common.glsl"

layout(location = CDT_ATTRIB_POSITION_TIME) in vec4 a_PositionTime;
layout(location = CDT_ATTRIB_ID) in uint a_Id;

flat out vec4 f_Texel;
flat out uvec2 f_Key;
flat out float f_Depth;

void main() {
  CdtTexel t = cdtTexelOf(a_PositionTime.xyz);
  f_Texel = vec4(a_PositionTime.xyz, float(a_Id));
  f_Key = uvec2(floatBitsToUint(t.depth), uint(gl_VertexID));
  f_Depth = t.depth;
  gl_Position = cdtTexelCentre(t);
}
