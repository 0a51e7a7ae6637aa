// Every light particle adds, to each voxel whose centre lies within u_range of it, its colour
// times 1 / (c + l d + q d^2) (texture 1) and the unit direction from the voxel to it times its
// intensity (texture 2) - seed 004, section 4's pseudo-code, with the attenuation's parentheses.
// ACCUMULATE_PAPER: the paper's imageLoad + imageStore into the RGBA16F textures, unsynchronised
// (updates are lost where invocations share a voxel). Otherwise: fixed-point integer atomics into
// six r32i images, resolved by lights_resolve.comp (exact and independent of order).
#include "lights_common.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Lights { LightParticle lights[]; };
uniform uint u_count;
uniform uint u_first;  // this dispatch's first light (GL allows 65,535 groups of 64 per dispatch)
uniform vec3 u_attenuation;  // constant, linear, quadratic
uniform float u_range;       // m

#ifdef ACCUMULATE_PAPER
layout(binding = 0, rgba16f) uniform image3D u_colourImage;
layout(binding = 1, rgba16f) uniform image3D u_directionImage;
#else
// Set when an add carried a voxel's sum past the int32 range (imageAtomicAdd returns the sum
// before it): render/lights/LightVolume.cpp then redoes the frame at a scale no voxel can wrap.
layout(std430, binding = 1) buffer Overflow { uint u_overflowed; };
bool wraps(int before, int add) {
  return add > 0 ? before > 2147483647 - add : before < (-2147483647 - 1) - add;
}
#define ADD_FIXED(image, value) \
  if (value != 0 && wraps(imageAtomicAdd(image, v, value), value)) atomicOr(u_overflowed, 1u)
layout(binding = 0, r32i) uniform iimage3D u_sum0;
layout(binding = 1, r32i) uniform iimage3D u_sum1;
layout(binding = 2, r32i) uniform iimage3D u_sum2;
layout(binding = 3, r32i) uniform iimage3D u_sum3;
layout(binding = 4, r32i) uniform iimage3D u_sum4;
layout(binding = 5, r32i) uniform iimage3D u_sum5;
#endif

void main() {
  uint i = u_first + gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec3 p = lights[i].position.xyz;
  vec4 c = lights[i].colour;
  // The voxel nearest the light, and the paper's int(range) + 1 voxels either side of it.
  ivec3 centre = ivec3(floor((p - u_origin) / u_voxelSize));
  int dist = int(u_range / u_voxelSize) + 1;
  ivec3 lo = max(centre - dist, u_boxLo);
  ivec3 hi = min(centre + dist, u_boxHi);
  for (int z = lo.z; z <= hi.z; ++z) {
    for (int y = lo.y; y <= hi.y; ++y) {
      for (int x = lo.x; x <= hi.x; ++x) {
        ivec3 v = ivec3(x, y, z);
        vec3 voxel = u_origin + (vec3(v) + 0.5) * u_voxelSize;
        float d = distance(p, voxel);
        if (d > u_range) continue;
        float attenuation = 1.0 / (u_attenuation.x + u_attenuation.y * d + u_attenuation.z * d * d);
        vec3 colour = attenuation * c.rgb;
        vec3 direction = d > 0.0 ? (p - voxel) / d * c.a : vec3(0.0);
#ifdef ACCUMULATE_PAPER
        imageStore(u_colourImage, v, imageLoad(u_colourImage, v) + vec4(colour, 0.0));
        imageStore(u_directionImage, v, imageLoad(u_directionImage, v) + vec4(direction, 0.0));
#else
        ivec3 fc = ivec3(round(colour * u_fixedScale));
        ivec3 fd = ivec3(round(direction * u_fixedScale));
        ADD_FIXED(u_sum0, fc.x);
        ADD_FIXED(u_sum1, fc.y);
        ADD_FIXED(u_sum2, fc.z);
        ADD_FIXED(u_sum3, fd.x);
        ADD_FIXED(u_sum4, fd.y);
        ADD_FIXED(u_sum5, fd.z);
#endif
      }
    }
  }
}
