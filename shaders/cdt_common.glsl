// Shared by the CDT shaders: the parameter block and the texel addressing of seed 000, section
// 3.2 (pseudo-code lines 2-4). cdtTexelOf() mirrors sph::cdt::texelOf() in sim/cdt/CdtCamera.cpp
// operation for operation: double arithmetic on float inputs (every product exact), `precise` so
// the compiler neither fuses nor reorders, so cdt-gl and cdt-cpu agree on every texel.
#include "cdt_constants.glsl"

// The C++ mirror is render/cdt/CdtGl.h, CdtParamsGpu (static_assert on its 128 bytes).
layout(std140, binding = CDT_PARAMS_BINDING) uniform CdtParams {
  mat4 u_ProjView;   // collision camera: projection * view
  ivec4 u_Texture;   // width, height (texels), layers, texel_collide_range r
  ivec4 u_Control;   // adaptive r cap, flags (CDT_FLAG_*), -, -
  vec4 u_Scalars;    // collision_range (m), step dt (s), speed_factor, cooldown (s)
  vec4 u_Scalars2;   // texels per metre at view depth 1, -, -, -
};

bool cdtFlag(int flag) { return (u_Control.y & flag) != 0; }

struct CdtTexel {
  bool onScreen;
  ivec2 texel;
  float depth;      // NDC z / 2 + 1/2, in [0, 1)
  double inverseW;  // 1 / clip w
};

CdtTexel cdtTexelOf(vec3 p) {
  CdtTexel t;
  t.onScreen = false;
  t.texel = ivec2(0);
  t.depth = 0.0;
  t.inverseW = 0.0LF;
  precise double px = double(p.x);
  precise double py = double(p.y);
  precise double pz = double(p.z);
  precise double cx = double(u_ProjView[0][0]) * px + double(u_ProjView[1][0]) * py +
                      double(u_ProjView[2][0]) * pz + double(u_ProjView[3][0]);
  precise double cy = double(u_ProjView[0][1]) * px + double(u_ProjView[1][1]) * py +
                      double(u_ProjView[2][1]) * pz + double(u_ProjView[3][1]);
  precise double cz = double(u_ProjView[0][2]) * px + double(u_ProjView[1][2]) * py +
                      double(u_ProjView[2][2]) * pz + double(u_ProjView[3][2]);
  precise double cw = double(u_ProjView[0][3]) * px + double(u_ProjView[1][3]) * py +
                      double(u_ProjView[2][3]) * pz + double(u_ProjView[3][3]);
  if (!(cw > 0.0LF)) return t;
  precise double inverseW = 1.0LF / cw;
  precise double nx = cx * inverseW;
  precise double ny = cy * inverseW;
  precise double nz = cz * inverseW;
  if (!(nx >= -1.0LF && nx < 1.0LF && ny >= -1.0LF && ny < 1.0LF && nz >= -1.0LF && nz < 1.0LF)) {
    return t;
  }
  precise double ux = (nx + 1.0LF) * 0.5LF * double(u_Texture.x);
  precise double uy = (ny + 1.0LF) * 0.5LF * double(u_Texture.y);
  int x = int(ux);
  int y = int(uy);
  if (x >= u_Texture.x || y >= u_Texture.y) return t;
  precise double depth = nz * 0.5LF + 0.5LF;
  t.onScreen = true;
  t.texel = ivec2(x, y);
  t.depth = float(depth);
  t.inverseW = inverseW;
  return t;
}

// Clip position that rasterises a point exactly onto texel `t` (its centre), or one outside the
// clip volume (clipped: nothing written) when the particle is not on the texture.
vec4 cdtTexelCentre(CdtTexel t) {
  if (!t.onScreen) return vec4(2.0, 2.0, 2.0, 1.0);
  vec2 ndc = (vec2(t.texel) + 0.5) / vec2(u_Texture.xy) * 2.0 - 1.0;
  return vec4(ndc, 0.0, 1.0);
}
