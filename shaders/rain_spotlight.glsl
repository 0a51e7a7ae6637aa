// The cone spotlight of seed 002 section 3.2, eq. (10)-(13), as DESIGN.md reads eq. (12); the
// CPU twin is sim/rain/Spotlight.h (tests/test_rain.cpp checks it on 10^6 points). u_spotOn is 0
// unless the scene's rain has a spotlight.
uniform int u_spotOn;
uniform vec3 u_spotPosition;   // apex, m
uniform vec3 u_spotDirection;  // unit axis D
uniform float u_spotHeight;    // m
uniform float u_spotBaseRadius;  // m
uniform vec3 u_spotColour;
uniform float u_spotIntensity;
uniform float u_spotSoftEdge;  // 0 = the paper's hard edge
uniform int u_spotFalloff;     // 0 = the paper

// How much of the light reaches p, in [0, 1].
float spotlightWeight(vec3 p) {
  if (u_spotOn == 0) return 0.0;
  vec3 ps = p - u_spotPosition;             // eq. (10)
  float updown = dot(ps, u_spotDirection);  // eq. (10)
  if (updown < 0.0 || updown > u_spotHeight) return 0.0;  // above the light, or past the cone
  float rCone = updown / u_spotHeight * u_spotBaseRadius;    // eq. (11)
  float distOrtho = length(ps - updown * u_spotDirection);   // eq. (12), as read
  float w;
  if (u_spotSoftEdge <= 0.0) {
    w = rCone >= distOrtho ? 1.0 : 0.0;  // eq. (13)
  } else {
    float inner = (1.0 - u_spotSoftEdge) * rCone;
    w = clamp((rCone - distOrtho) / max(rCone - inner, 1e-30), 0.0, 1.0);
  }
  if (u_spotFalloff != 0) w /= 1.0 + (updown / u_spotHeight) * (updown / u_spotHeight);
  return w;
}
