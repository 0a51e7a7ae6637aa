// Shared by the light-volume compute passes (render/lights/LightVolume.cpp; seed 004 section 4).
// One light particle: position (m) and, in `colour`, its colour times intensity (rgb) and its
// intensity (a), the paper's "Particle Light Color" whose alpha weights the direction.
struct LightParticle {
  vec4 position;
  vec4 colour;
};
// Voxel v of the volume covers [origin + v h, origin + (v + 1) h]; its value is the light at its
// centre origin + (v + 1/2) h (the paper measures to the integer corner; DESIGN.md).
uniform vec3 u_origin;
uniform float u_voxelSize;
uniform ivec3 u_voxels;
// The voxels this frame accumulates and resolves, bounds included: the whole volume, or with
// lights.cull the box a frame's camera may read (render/lights/LightCulling.h).
uniform ivec3 u_boxLo;
uniform ivec3 u_boxHi;
// The fixed-point scale of the atomic sums: a voxel holds round(value * scale) in an int;
// 16384 / the lights' intensity, less in a frame where that would wrap a voxel
// (render/lights/LightVolume.cpp, fixedScale and safeFixedScale).
uniform float u_fixedScale;
