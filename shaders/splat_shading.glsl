// The lighting model of render/frame/Lighting.h, per vertex (Gouraud) for the splat renderers. Keep the
// two in step: tests/test_splat_gl.cpp renders a flat splat and compares with Lighting's shade().
uniform vec3 u_toLight;
uniform vec3 u_base;
uniform float u_ambient;
uniform float u_diffuse;
uniform float u_specular;
uniform float u_shininess;
uniform int u_environment;
uniform vec3 u_horizon;
uniform vec3 u_zenith;
uniform float u_fresnelMin;

#include "extra_lights.glsl"

vec3 shadeSurface(vec3 n, vec3 toEye) {
  float nl = max(dot(n, u_toLight), 0.0);
  vec3 halfway = normalize(u_toLight + toEye);
  float nh = max(dot(n, halfway), 0.0);
  vec3 c = u_ambient * u_base + u_diffuse * nl * u_base + vec3(u_specular * pow(nh, u_shininess));
#ifndef SPH_NO_ENVIRONMENT  // the solids never reflect the sky: llvmpipe runs a switched-off branch
  if (u_environment != 0) {
    vec3 r = 2.0 * dot(n, toEye) * n - toEye;
    float up = clamp(r.y, 0.0, 1.0);
    vec3 sky = (1.0 - up) * u_horizon + up * u_zenith;
    float cosine = clamp(dot(n, toEye), 0.0, 1.0);
    float fresnel = u_fresnelMin + (1.0 - u_fresnelMin) * pow(1.0 - cosine, 5.0);
    c = (1.0 - fresnel) * c + fresnel * sky;
  }
#endif
  return clamp(c, 0.0, 1.0);
}

// The same at a world position, with the position-dependent lights of extra_lights.glsl added
// before the clamp. What the solids (per pixel) and the splats (per vertex) call.
vec3 shadeSurfaceAt(vec3 position, vec3 n, vec3 toEye) {
  return clamp(sceneLightScale() * shadeSurface(n, toEye) + extraLight(u_base, position, n, toEye),
               0.0, 1.0);
}
