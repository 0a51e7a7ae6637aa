// Lights beyond the scene's directional light, which depend on where the lit point is: the
// rain's spotlight (seed 002, section 3.2) and the particle lights' 3D textures (seed 004). Each
// system adds its term here behind a uniform switch that is off unless its scene section exists,
// so a scene without them shades exactly as before. `base` is the surface's own colour (linear
// RGB), `position` its world position (m), `n` its outward unit normal, `toEye` the unit vector
// to the eye.

// ---- Particle lights (seed 004; render/lights/LightVolume.cpp sets these, docs/lights.md) ----
uniform int u_particleLights;  // 0: no `lights` section, nothing below runs
layout(binding = 6) uniform sampler3D u_lightColour;     // sum of attenuated colours per voxel
layout(binding = 7) uniform sampler3D u_lightDirection;  // sum of intensity-weighted directions
uniform vec3 u_lightOrigin;    // m, the volume's lowest corner
uniform float u_lightVoxel;    // m, voxel side
uniform ivec3 u_lightVoxels;   // voxels per axis
uniform int u_lightFilter;     // 0 nearest, 1 trilinear, 2 tricubic (Catmull-Rom)
uniform float u_lightTension;  // tricubic: 0 = Catmull-Rom, 1 = zero tangents
uniform int u_lightOversampling;  // samples per axis within one voxel (1 = off)
uniform vec3 u_lightMaterial;  // diffuse, specular, shininess of the surfaces under these lights
uniform int u_lightTerms;      // bit 0: diffuse, bit 1: specular (the error figures split them)
uniform float u_lightRoom;     // lights.room_light: the scene's own light is scaled by it

// Voxel v's value, zero outside the volume (nothing was accumulated there).
vec4 lightTexel(sampler3D s, ivec3 v) {
  if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, u_lightVoxels))) return vec4(0.0);
  return texelFetch(s, v, 0);
}

// Cardinal-spline weights of the 4 samples around f in [0, 1) (seed 004 section 6.1; s = (1 -
// tension) / 2, s = 1/2 is Catmull-Rom).
vec4 cardinalWeights(float f, float s) {
  float f2 = f * f, f3 = f2 * f;
  return vec4(s * (-f3 + 2.0 * f2 - f), (2.0 - s) * f3 + (s - 3.0) * f2 + 1.0,
              (s - 2.0) * f3 + (3.0 - 2.0 * s) * f2 + s * f, s * (f3 - f2));
}

// The light texture at continuous voxel coordinate g ((position - origin) / voxel side; voxel
// centres at integer + 1/2) through the chosen filter.
vec4 lightFiltered(sampler3D s, vec3 g) {
  if (u_lightFilter == 0) return lightTexel(s, ivec3(floor(g)));
  if (u_lightFilter == 1) return textureLod(s, g / vec3(u_lightVoxels), 0.0);
  vec3 c = g - 0.5;
  ivec3 i = ivec3(floor(c));
  vec3 f = c - vec3(i);
  float sp = 0.5 * (1.0 - u_lightTension);
  vec4 wx = cardinalWeights(f.x, sp), wy = cardinalWeights(f.y, sp), wz = cardinalWeights(f.z, sp);
  vec4 sum = vec4(0.0);
  for (int z = 0; z < 4; ++z) {
    for (int y = 0; y < 4; ++y) {
      vec4 row = vec4(0.0);
      for (int x = 0; x < 4; ++x) row += wx[x] * lightTexel(s, i + ivec3(x - 1, y - 1, z - 1));
      sum += wz[z] * wy[y] * row;
    }
  }
  return sum;
}

// Oversampling (seed 004 section 6.2): the mean of n^3 filtered samples spread over one voxel
// around the point.
vec4 lightSampled(sampler3D s, vec3 g) {
  int n = u_lightOversampling;
  if (n <= 1) return lightFiltered(s, g);
  vec4 sum = vec4(0.0);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        sum += lightFiltered(s, g + (vec3(x, y, z) + 0.5) / float(n) - 0.5);
  return sum / float(n * n * n);
}

// Phong diffuse and specular of the particle lights at a point (seed 004 section 5): the colour
// texture is the light reaching the point, the renormalised direction texture the light vector.
vec3 particleLight(vec3 base, vec3 position, vec3 n, vec3 toEye) {
  vec3 g = (position - u_lightOrigin) / u_lightVoxel;
  vec3 colour = max(lightSampled(u_lightColour, g).rgb, vec3(0.0));
  vec3 direction = lightSampled(u_lightDirection, g).xyz;
  float len = length(direction);
  if (len < 1e-6) return vec3(0.0);
  vec3 l = direction / len;
  vec3 c = vec3(0.0);
  if ((u_lightTerms & 1) != 0) c += u_lightMaterial.x * base * colour * max(dot(n, l), 0.0);
  if ((u_lightTerms & 2) != 0) {
    vec3 r = reflect(-l, n);
    c += u_lightMaterial.y * colour * pow(max(dot(r, toEye), 0.0), u_lightMaterial.z);
  }
  return c;
}

// How much of the scene's own (directional, sky) light remains: 1 unless a system dims the room.
float sceneLightScale() {
  return u_particleLights != 0 ? u_lightRoom : 1.0;
}

// ---- The rain's spotlight (seed 002 section 3.2; render/frame/SpotlightUniforms.h) ----
#include "rain_spotlight.glsl"

vec3 extraLight(vec3 base, vec3 position, vec3 n, vec3 toEye) {
  vec3 c = vec3(0.0);
#ifndef SPH_NO_PARTICLE_LIGHTS
  if (u_particleLights != 0) c += particleLight(base, position, n, toEye);
#endif
  // The rain's cone spotlight (render/frame/SpotlightUniforms.h): Lambert diffuse inside the cone
  // of eq. (10)-(12), the same membership test the drops take their colour from. SPH_NO_SPOTLIGHT:
  // a program for frames without one (llvmpipe runs a branch a uniform switches off, every pixel).
#ifndef SPH_NO_SPOTLIGHT
  float w = spotlightWeight(position);
  if (w > 0.0) {
    vec3 toLight = normalize(u_spotPosition - position);
    c += w * u_spotIntensity * u_spotColour * base * max(dot(n, toLight), 0.0);
  }
#endif
  return c;
}
