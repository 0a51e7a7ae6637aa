// The G-buffer of the deferred particle lights (lights.pipeline "deferred"; seed 004 Fig. 11;
// render/frame/DeferredTarget.h): what a surface program built with SPH_GBUFFER writes instead of
// its colour, and what shaders/deferred_lighting.frag reads back, one surface per pixel.
layout(location = 0) out vec4 g_lit;       // linear colour lit by all but the particle lights;
                                           // alpha 1 where a surface was drawn
layout(location = 1) out vec4 g_albedo;    // the surface colour the particle lights multiply
layout(location = 2) out vec4 g_position;  // world position, m
layout(location = 3) out vec4 g_normal;    // outward unit normal; alpha 1 on the water

// `water`: the error figures' normal target is the water's alone (splat.frag writes it forward).
void writeGBuffer(vec3 lit, vec3 albedo, vec3 position, vec3 n, bool water) {
  g_lit = vec4(lit, 1.0);
  g_albedo = vec4(albedo, 1.0);
  g_position = vec4(position, 1.0);
  g_normal = vec4(n, water ? 1.0 : 0.0);
}
