#version 450 core
// The collision pass of seed 000 / 001, section 3.2 (pseudo-code "ParticleCollisionPass"): one
// invocation per particle. It reads the texture the previous step wrote (u_Layers), finds the
// nearest stored position within collision_range among the (2r+1)^2 texels around its base texel
// in every layer, responds, and writes the new state by transform feedback (xfb_buffer 0, the
// other of the two ping-pong buffers; 1: diagnostics; 2: where the new position goes in the next
// texture). With the paper's raster write it also rasterises the new position into its texel of
// the next texture (cdt_write.frag); otherwise the rasteriser is off and cdt_write.comp writes.
//
// Mirror of sph::cdt::CdtCpu::step in sim/cdt/CdtCpu.cpp: the same double arithmetic on float inputs,
// rounded to float at the same places; `precise` keeps the compiler from fusing or reordering.
#include "cdt_common.glsl"

// Vertex layout = transform feedback layout: render/cdt/CdtGl.h, CdtParticleGpu (48 bytes).
layout(location = CDT_ATTRIB_POSITION_TIME) in vec4 a_PositionTime;  // m, a_CollideTime (s)
layout(location = CDT_ATTRIB_VELOCITY) in vec3 a_Velocity;           // m/s
layout(location = CDT_ATTRIB_ID) in uint a_Id;
layout(location = CDT_ATTRIB_ACCELERATION) in vec3 a_Acceleration;   // m/s^2

// The texture the previous step wrote, one array layer per depth-peeled layer.
layout(binding = CDT_LAYER_UNIT) uniform sampler2DArray u_Layers;

// xfb_buffer numbers are literals (Mesa 22 crashes on a named constant there); they are
// sph::cdt::kXfbState, kXfbDiagnostics and kXfbWriteKeys, checked by tests/test_cdt_cpu.cpp.
layout(xfb_buffer = 0, xfb_stride = 48) out;
layout(xfb_buffer = 0, xfb_offset = 0) flat out vec4 v_PositionTime;
layout(xfb_buffer = 0, xfb_offset = 16) flat out vec3 v_Velocity;
layout(xfb_buffer = 0, xfb_offset = 28) flat out uint v_Id;
layout(xfb_buffer = 0, xfb_offset = 32) flat out vec3 v_Acceleration;
// partner id, candidates in range, base texel x | y << 16, r searched (sph::cdt::Diagnostics).
layout(xfb_buffer = 1, xfb_stride = 16, xfb_offset = 0) flat out uvec4 v_Diag;
// Where the new position goes in the next texture: texel y * width + x (CDT_OFFSCREEN if none)
// and its depth bits, for the compute-shader write (cdt_write.comp), which so never repeats the
// projection.
layout(xfb_buffer = 2, xfb_stride = 8, xfb_offset = 0) flat out uvec2 v_WriteKey;

// To cdt_write.frag: the new position's texel content and key.
flat out vec4 f_Texel;
flat out uvec2 f_Key;
flat out float f_Depth;

void main() {
  precise double h = double(u_Scalars.y);
  precise double range = double(u_Scalars.x);
  precise double range2 = range * range;
  bool integrate = cdtFlag(CDT_FLAG_INTEGRATE);

  // Start of the step (p0, v0) and the end without a collision (pf, vf).
  vec3 p0, v0, pf, vf;
  if (integrate) {
    // The paper's free branch, lines 26-30: temp = v + g tick; pos += temp tick.
    p0 = a_PositionTime.xyz;
    v0 = a_Velocity;
    precise dvec3 vd = dvec3(a_Velocity) + dvec3(a_Acceleration) * h;
    vf = vec3(vd);
    precise dvec3 pd = dvec3(a_PositionTime.xyz) + dvec3(vf) * h;
    pf = vec3(pd);
  } else {
    // Already integrated by the SPH step: reconstruct where it started.
    pf = a_PositionTime.xyz;
    vf = a_Velocity;
    precise dvec3 pd = dvec3(a_PositionTime.xyz) - dvec3(a_Velocity) * h;
    precise dvec3 vd = dvec3(a_Velocity) - dvec3(a_Acceleration) * h;
    p0 = vec3(pd);
    v0 = vec3(vd);
  }

  uvec4 diag = uvec4(CDT_NO_PARTNER, 0u, CDT_OFFSCREEN, 0u);
  bool found = false;
  precise double best = range2;
  vec3 partner = vec3(0.0);
  vec3 cur = p0;
  CdtTexel base = cdtTexelOf(p0);
  // Line 8: only particles whose cooldown has run out search.
  if (cdtFlag(CDT_FLAG_TEXTURE_VALID) && base.onScreen && a_PositionTime.w < 0.0) {
    bool search = true;
    bool texelPosition = cdtFlag(CDT_FLAG_TEXEL_POSITION);
    if (texelPosition) {
      // Line 5: curr_pos = whatever the base texel holds.
      vec4 c = texelFetch(u_Layers, ivec3(base.texel, 0), 0);
      search = c.w >= 0.0;
      cur = c.xyz;
    }
    if (search) {
      int r = u_Texture.w;
      if (cdtFlag(CDT_FLAG_ADAPTIVE_RANGE)) {
        // sph::cdt::adaptiveTexelRange: the range projected to texels, rounded up, in [1, cap].
        precise double texels = ceil(range * double(u_Scalars2.x) * base.inverseW);
        r = int(clamp(texels, 1.0LF, double(u_Control.x)));
      }
      diag.z = uint(base.texel.x) | (uint(base.texel.y) << 16);
      diag.w = uint(r);
      for (int l = 0; l < u_Texture.z; ++l) {
        for (int ty = -r; ty <= r; ++ty) {
          int y = base.texel.y + ty;
          if (y < 0 || y >= u_Texture.y) continue;
          for (int tx = -r; tx <= r; ++tx) {
            // Lines 12-13: the paper skips the base texel it read as curr_pos.
            if (texelPosition && tx == 0 && ty == 0) continue;
            int x = base.texel.x + tx;
            if (x < 0 || x >= u_Texture.x) continue;
            vec4 t = texelFetch(u_Layers, ivec3(x, y, l), 0);
            if (t.w < 0.0) continue;  // empty
            uint other = uint(t.w);
            if (other == a_Id) continue;  // its own previous position
            precise double dx = double(cur.x) - double(t.x);
            precise double dy = double(cur.y) - double(t.y);
            precise double dz = double(cur.z) - double(t.z);
            precise double d2 = dx * dx + dy * dy + dz * dz;
            if (!(d2 < range2)) continue;
            diag.y += 1u;
            // Lines 16-19: the nearest in range wins, the first of equals.
            if (d2 < best) {
              best = d2;
              found = true;
              diag.x = other;
              partner = t.xyz;
            }
          }
        }
      }
    }
  }

  vec3 np, nv;
  float nt;
  if (!found) {
    np = pf;
    nv = vf;
    precise double td = double(a_PositionTime.w) - h;  // line 29
    nt = float(td);
  } else {
    // Line 22: away from the partner, from curr_pos.
    precise double len = sqrt(best);
    precise dvec3 dir;
    if (len > 0.0LF) {
      dir = (dvec3(cur) - dvec3(partner)) / len;
    } else {
      dir = dvec3(0.0LF, a_Id > diag.x ? 1.0LF : -1.0LF, 0.0LF);
    }
    precise dvec3 npd, nvd;
    if (cdtFlag(CDT_FLAG_PAPER_RESPONSE)) {
      // Lines 21-24, with the step as the tick (docs/collision.md).
      precise double speed2 = double(v0.x) * double(v0.x) + double(v0.y) * double(v0.y) +
                              double(v0.z) * double(v0.z);
      precise double speed = double(u_Scalars.z) * sqrt(speed2);
      nvd = dir * speed;
      npd = dvec3(p0) + nvd * h;
    } else {
      // Separation out to the range (half the overlap) and no velocity towards the partner.
      precise double push = 0.5LF * (range - len);
      precise double vn = double(vf.x) * dir.x + double(vf.y) * dir.y + double(vf.z) * dir.z;
      precise double remove = vn < 0.0LF ? vn : 0.0LF;
      npd = dvec3(pf) + dir * push;
      nvd = dvec3(vf) - remove * dir;
    }
    np = vec3(npd);
    nv = vec3(nvd);
    precise double td = double(a_PositionTime.w) - h;
    nt = u_Scalars.w > 0.0 ? u_Scalars.w : float(td);
  }

  v_PositionTime = vec4(np, nt);
  v_Velocity = nv;
  v_Id = a_Id;
  v_Acceleration = a_Acceleration;
  v_Diag = diag;

  CdtTexel written = cdtTexelOf(np);
  uint writeTexel = uint(written.texel.y * u_Texture.x + written.texel.x);
  v_WriteKey = uvec2(written.onScreen ? writeTexel : CDT_OFFSCREEN, floatBitsToUint(written.depth));
  f_Texel = vec4(np, float(a_Id));
  f_Key = uvec2(floatBitsToUint(written.depth), uint(gl_VertexID));
  f_Depth = written.depth;
  gl_Position = cdtTexelCentre(written);
}
