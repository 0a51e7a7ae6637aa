// Lights beyond the scene's directional light, which depend on where the lit point is: the
// rain's spotlight (seed 002, section 3.2) and the particle lights' 3D textures (seed 004). Each
// system adds its term here behind a uniform switch that is off unless its scene section exists,
// so a scene without them shades exactly as before. `base` is the surface's own colour (linear
// RGB), `position` its world position (m), `n` its outward unit normal, `toEye` the unit vector
// to the eye.
#include "rain_spotlight.glsl"

vec3 extraLight(vec3 base, vec3 position, vec3 n, vec3 toEye) {
  vec3 c = vec3(0.0);
  // The rain's cone spotlight (render/splat/SpotlightUniforms.h): Lambert diffuse inside the cone
  // of eq. (10)-(12), the same membership test the drops take their colour from.
  float w = spotlightWeight(position);
  if (w > 0.0) {
    vec3 toLight = normalize(u_spotPosition - position);
    c += w * u_spotIntensity * u_spotColour * base * max(dot(n, toLight), 0.0);
  }
  return c;
}
