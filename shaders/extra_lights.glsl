// Lights beyond the scene's directional light, which depend on where the lit point is: the
// rain's spotlight (seed 002, section 3.2) and the particle lights' 3D textures (seed 004). Each
// system adds its term here behind a uniform switch that is off unless its scene section exists,
// so a scene without them shades exactly as before. `base` is the surface's own colour (linear
// RGB), `position` its world position (m), `n` its outward unit normal, `toEye` the unit vector
// to the eye.
vec3 extraLight(vec3 base, vec3 position, vec3 n, vec3 toEye) {
  return vec3(0.0);
}
