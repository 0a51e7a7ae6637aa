#version 450 core
// The deferred pipeline's one full-screen lighting pass (lights.pipeline "deferred"; seed 004,
// Fig. 11; render/frame/DeferredTarget.cpp): for each pixel the G-buffer holds a surface
// (shaders/gbuffer_out.glsl), the particle lights' Phong diffuse and specular at its world
// position (extra_lights.glsl's particleLight, the forward shaders' very term) added to the rest of
// its lighting, clamped and sRGB-encoded as the forward shaders write it; its depth restored so the
// translucent water and later layers are depth tested against the deferred-lit frame.
// SPH_CPU_PARTICLE_LIGHTS (lights.shade "cpu"; render/lights/CpuShading.h): each pixel's whole
// colour (lit + the particle lights' term, clamped and sRGB-encoded, alpha 1 where a surface is)
// was computed on the CPU from this G-buffer and is copied from u_gColour; no 3D texture is
// sampled and nothing encoded here (llvmpipe's cost of this pass, docs/benchmarks.md).
#include "extra_lights.glsl"

layout(binding = 0) uniform sampler2D u_gLit;
layout(binding = 1) uniform sampler2D u_gAlbedo;
layout(binding = 2) uniform sampler2D u_gPosition;
layout(binding = 3) uniform sampler2D u_gNormal;
layout(binding = 4) uniform sampler2D u_gDepth;
uniform vec3 u_eye;
uniform bool u_normals;  // the second target takes the water's normals (the error figures' frame)
#ifdef SPH_CPU_PARTICLE_LIGHTS
layout(binding = 5) uniform sampler2D u_gColour;  // RGBA8
#endif

layout(location = 0) out vec4 o_colour;
layout(location = 1) out vec4 o_normal;  // the error figures' normal and coverage (splat.frag)

vec3 toSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
#ifdef SPH_CPU_PARTICLE_LIGHTS
  vec4 encoded = texelFetch(u_gColour, px, 0);
  if (encoded.a < 0.5) discard;  // nothing drawn here: the cleared background stays
  o_colour = vec4(encoded.rgb, 1.0);
  if (u_normals) {
    vec4 normal = texelFetch(u_gNormal, px, 0);
    o_normal = normal.a > 0.5 ? vec4(normal.xyz, 1.0) : vec4(0.0);  // the water's only, as forward
  }
#else
  vec4 lit = texelFetch(u_gLit, px, 0);
  if (lit.a < 0.5) discard;  // nothing drawn here: the cleared background stays
  vec4 normal = texelFetch(u_gNormal, px, 0);
  vec3 n = normal.xyz;
  vec3 position = texelFetch(u_gPosition, px, 0).xyz;
  vec3 albedo = texelFetch(u_gAlbedo, px, 0).rgb;
  vec3 c = lit.rgb + particleLight(albedo, position, n, normalize(u_eye - position));
  o_colour = vec4(toSrgb(c), 1.0);
  o_normal = normal.a > 0.5 ? vec4(n, 1.0) : vec4(0.0);  // the water's only, as forward
#endif
  gl_FragDepth = texelFetch(u_gDepth, px, 0).r;
}
