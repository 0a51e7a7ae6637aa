// The SD iso-surface of a frame's density field as a triangle mesh: the
// surface the splat renderer draws and the reference ray-marcher shows (docs/rendering.md),
// for tools that want geometry (Blender, Houdini: docs/mesh.md).
//
// Marching cubes (Lorensen & Cline 1987, table derived in CaseTable.h) over a lattice of cell
// `cellSize`, kept sparse: only blocks of 8^3 lattice points within R + one cell of a particle
// exist (the field is zero elsewhere), so memory follows the fluid, not its bounding box.
// D at the lattice points is the same sum the renderer evaluates (DensityField::density); a
// vertex sits where D crosses SD on a lattice edge (linear interpolation) and its normal is
// -gradD there, normalised: outward, towards lower density. Vertices are shared between the
// triangles that meet at them, and with the crack-free table the mesh of a blob that stays
// clear of nothing is closed: every edge belongs to exactly two triangles.
//
// Threads: blocks are independent and their output is concatenated in block order, so the mesh
// is the same, bit for bit, for any number of OpenMP threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/splat/DensityField.h"

namespace sph::render::mesh {

struct SurfaceMesh {
  std::vector<float> positions;          // x y z per vertex (m)
  std::vector<float> normals;            // unit outward normal per vertex
  std::vector<std::uint32_t> triangles;  // 3 vertex indices each, counter-clockwise from outside
  std::size_t vertexCount() const { return positions.size() / 3; }
  std::size_t triangleCount() const { return triangles.size() / 3; }
};

struct MeshTimings {
  double lattice = 0;    // s: which blocks exist, D at their points
  double vertices = 0;   // s: edge crossings and their normals
  double triangles = 0;  // s
  double total() const { return lattice + vertices + triangles; }
};

struct MeshStats {
  std::size_t blocks = 0;         // blocks of 8^3 lattice points evaluated
  std::size_t latticePoints = 0;  // D evaluations (blocks x 512)
  std::size_t surfaceBlocks = 0;  // blocks where SD is crossed (the others skip the marching)
  MeshTimings timings;
};

// The iso-surface D = SD of `field`, on a lattice of edge `cellSize` (m). Throws InputError if
// the particles span so many cells that the block index would not fit in memory (more than 2^26
// blocks) or the lattice near the particles would have more than 2^31 points (8 GB): the
// message asks for a larger cell.
SurfaceMesh extractSurface(const splat::DensityField& field, float SD, float cellSize,
                           MeshStats* stats = nullptr);

// Measures of a mesh, for tests and benchmarks.
struct MeshCheck {
  std::size_t edges = 0;             // distinct undirected edges
  std::size_t boundaryEdges = 0;     // in one triangle only (holes)
  std::size_t nonManifoldEdges = 0;  // in three or more
  std::size_t misorientedEdges = 0;  // used twice in the same direction (flipped neighbours)
  bool watertight() const { return edges > 0 && boundaryEdges == 0 && nonManifoldEdges == 0; }
};
MeshCheck checkEdges(const SurfaceMesh& mesh);
double surfaceArea(const SurfaceMesh& mesh);     // m^2
double enclosedVolume(const SurfaceMesh& mesh);  // m^3, signed: > 0 for outward winding

}  // namespace sph::render::mesh
