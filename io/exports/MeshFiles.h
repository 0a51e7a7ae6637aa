// A triangle mesh (the water surface of `sphsplat mesh`, render/mesh) as a file Blender, Houdini,
// MeshLab and meshio read (docs/mesh.md):
// - PLY, binary little-endian: `vertex` with float x y z nx ny nz, `face` with a uchar count and
//   int indices (`vertex_indices`), a comment line per entry of `comments`;
// - Wavefront OBJ: `v`, `vn` and `f a//a b//b c//c` (1-based), comments as `#` lines. Text, with
//   floats written shortest-round-trip (std::to_chars), so values survive exactly.
// Triangles are counter-clockwise seen from outside, which is what both formats take for the front.
// Write through io::AtomicOutput (io/UserFiles.h) so a file appears complete or not at all.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace sph::io::exports {

struct MeshView {
  const float* positions = nullptr;  // 3 per vertex
  const float* normals = nullptr;    // 3 per vertex (unit)
  std::size_t vertices = 0;
  const std::uint32_t* triangles = nullptr;  // 3 per triangle
  std::size_t triangleCount = 0;
  std::vector<std::string> comments;  // one line each, no newlines
};

// Throw InputError naming `what` ("results/mesh_00007.ply") if the write fails.
void writeMeshPly(std::FILE* out, const MeshView& mesh, const std::string& what);
void writeMeshObj(std::FILE* out, const MeshView& mesh, const std::string& what);

}  // namespace sph::io::exports
