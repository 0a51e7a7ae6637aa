#version 450 core
// The atomic path's second pass: each voxel's six fixed-point sums become the two RGBA16F light
// textures the shading samples (render/lights/LightVolume.cpp).
#include "lights_common.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(binding = 0, r32i) uniform readonly iimage3D u_sum0;
layout(binding = 1, r32i) uniform readonly iimage3D u_sum1;
layout(binding = 2, r32i) uniform readonly iimage3D u_sum2;
layout(binding = 3, r32i) uniform readonly iimage3D u_sum3;
layout(binding = 4, r32i) uniform readonly iimage3D u_sum4;
layout(binding = 5, r32i) uniform readonly iimage3D u_sum5;
layout(binding = 6, rgba16f) uniform writeonly image3D u_colourImage;
layout(binding = 7, rgba16f) uniform writeonly image3D u_directionImage;

void main() {
  ivec3 v = u_boxLo + ivec3(gl_GlobalInvocationID);
  if (any(greaterThan(v, u_boxHi))) return;
  vec3 colour = vec3(imageLoad(u_sum0, v).x, imageLoad(u_sum1, v).x, imageLoad(u_sum2, v).x);
  vec3 direction = vec3(imageLoad(u_sum3, v).x, imageLoad(u_sum4, v).x, imageLoad(u_sum5, v).x);
  // RGBA16F holds up to 65504: a brighter voxel saturates there (not infinity); the direction is
  // only used normalised, so a longer one is scaled down whole, keeping where it points.
  const float halfMax = 65504.0;
  colour = min(colour / u_fixedScale, vec3(halfMax));
  direction /= u_fixedScale;
  float longest = max(max(abs(direction.x), abs(direction.y)), abs(direction.z));
  if (longest > halfMax) direction *= halfMax / longest;
  imageStore(u_colourImage, v, vec4(colour, 0.0));
  imageStore(u_directionImage, v, vec4(direction, 0.0));
}
