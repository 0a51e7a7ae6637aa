// Triangle meshes of the scene's solids (tank, block, cup, sphere, plane: sim/scene/Scene.h's
// BoundaryShape), for drawing them opaque and lit in the same frame as the water: the particle
// lights need surfaces to fall on, and the showcase's cup and tray (scenes/pour.json) are seen. CPU
// only: positions and unit normals pointing out of the solid (into the fluid's side), triangles
// wound counter-clockwise seen from that side, so back-face culling removes the faces turned
// away from the eye: a tank is drawn as a cut-away (its inside and rim only), so seen from
// outside it shows the water, its floor and far walls through its near walls; a cup shows its
// outside and, from above, its inside.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/scene/Scene.h"
#include "sim/Types.h"

namespace sph::render::solids {

// One vertex as the solid shaders read it (shaders/solid.vert: location 0 position, 1 normal).
struct SolidVertex {
  float position[3];  // m
  float normal[3];    // unit, out of the solid
};
static_assert(sizeof(SolidVertex) == 24, "matches shaders/solid.vert's vertex layout");

struct SolidMesh {
  std::vector<SolidVertex> vertices;
  std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
  void append(const SolidMesh& other);
};

// The surface of `shape`; containers (tank, cup) are shells `thickness` metres thick, as
// sim/scene/Solid.h has them. A plane is cut to the shadow of `domain`. `segments`: around a cup or a
// sphere's equator (a sphere has segments / 2 rings); SolidRenderer picks them for each draw's
// size on screen (ScreenTessellation.h).
SolidMesh tessellate(const scene::BoundaryShape& shape, const Aabb& domain, float thickness,
                     int segments = 64);

}  // namespace sph::render::solids
