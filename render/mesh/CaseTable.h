// The marching-cubes case table (Lorensen & Cline 1987), derived here from one rule instead of
// typed in: for each of the 256 inside/outside patterns of a cube's corners, the triangles of
// the iso-surface inside the cube, as triples of cube edges.
//
// Derivation (CaseTable.cpp): on every face of the cube the crossed edges (inside at one end,
// outside at the other) are paired into segments; a face with four crossed edges (inside corners
// on a diagonal, the ambiguous face) always cuts off each inside corner on its own. The rule looks
// at the face alone, so the two cubes sharing a face draw the same segments there and the surface
// has no cracks (the 15-case table's complement symmetry breaks exactly this). Each crossed edge
// lies on two faces, so the segments join into closed loops; each loop is fanned into triangles,
// wound counter-clockwise seen from outside (from the low-density side).
//
// Corner c of a cube sits at (c & 1, c >> 1 & 1, c >> 2 & 1); edge e runs from corner
// kEdgeCorner[e] along axis kEdgeAxis[e].
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace sph::render::mesh {

struct CubeEdges {
  std::array<std::uint8_t, 12> corner;  // lower corner of each edge
  std::array<std::uint8_t, 12> axis;    // 0 x, 1 y, 2 z
};
const CubeEdges& cubeEdges();

// Triangles of one case: 3 edge indices each. `inside` bit c set: corner c is inside (D >= SD).
struct CubeCase {
  std::uint8_t count = 0;                  // triangles
  std::array<std::uint8_t, 3 * 12> edges;  // at most 12 triangles (4 loops of 3, ...)
};
const std::array<CubeCase, 256>& cubeCases();

}  // namespace sph::render::mesh
