#version 450 core
// Our texture write (collision.texture_write = "atomic", the default): the same texture as the
// paper's rasterised points with a depth test (cdt_write.frag), made by one invocation per
// particle and atomic minima, which llvmpipe runs on every core while it rasterises points one by
// one. The collision pass already projected each new position (v_WriteKey: texel, depth bits).
// Per layer, three dispatches separated by image barriers (u_Stage):
//   0: atomicMin of the depth bits at the particle's texel (depth >= 0, so bits order as values);
//   1: among the particles at that minimal depth, atomicMin of the draw index (the depth test's
//      "first drawn wins" among equal depths);
//   2: the particle holding both writes its position and id.
// Layers after the first only consider particles whose (depth, index) comes after the previous
// layer's key at their texel: depth peeling.
#include "cdt_common.glsl"

layout(local_size_x = CDT_WRITE_GROUP_SIZE) in;

// The transform feedback outputs: render/cdt/CdtGl.h, CdtParticleGpu (48 bytes, std430), and the
// write keys (8 bytes).
struct CdtParticle {
  vec4 positionTime;
  vec3 velocity;
  uint id;
  vec3 acceleration;
  float unused;
};
layout(std430, binding = CDT_PARTICLE_BINDING) readonly buffer CdtParticles {
  CdtParticle particles[];
};
layout(std430, binding = CDT_WRITE_KEY_BINDING) readonly buffer CdtWriteKeys {
  uvec2 writeKeys[];
};

layout(rgba32f, binding = CDT_IMAGE_COLOUR) uniform writeonly image2D u_Colour;
layout(r32ui, binding = CDT_IMAGE_DEPTH_KEY) uniform coherent uimage2D u_DepthKey;
layout(r32ui, binding = CDT_IMAGE_INDEX_KEY) uniform coherent uimage2D u_IndexKey;
layout(r32ui, binding = CDT_IMAGE_PREVIOUS_DEPTH) uniform readonly uimage2D u_PreviousDepth;
layout(r32ui, binding = CDT_IMAGE_PREVIOUS_INDEX) uniform readonly uimage2D u_PreviousIndex;

uniform int u_Stage;
uniform int u_Peel;
uniform uint u_Count;
uniform uint u_First;  // the dispatch's first particle: GL caps a dispatch at 65,535 groups

void main() {
  uint index = u_First + gl_GlobalInvocationID.x;
  if (index >= u_Count) return;
  uvec2 key = writeKeys[index];
  if (key.x == CDT_OFFSCREEN) return;
  ivec2 texel = ivec2(int(key.x % uint(u_Texture.x)), int(key.x / uint(u_Texture.x)));
  uint depth = key.y;
  if (u_Peel != 0) {
    uint previousDepth = imageLoad(u_PreviousDepth, texel).x;
    uint previousIndex = imageLoad(u_PreviousIndex, texel).x;
    bool after = depth > previousDepth || (depth == previousDepth && index > previousIndex);
    if (!after) return;
  }
  if (u_Stage == 0) {
    imageAtomicMin(u_DepthKey, texel, depth);
  } else if (u_Stage == 1) {
    if (imageLoad(u_DepthKey, texel).x == depth) imageAtomicMin(u_IndexKey, texel, index);
  } else {
    if (imageLoad(u_DepthKey, texel).x == depth && imageLoad(u_IndexKey, texel).x == index) {
      CdtParticle p = particles[index];
      imageStore(u_Colour, texel, vec4(p.positionTime.xyz, float(p.id)));
    }
  }
}
