// The order the solids are drawn in: nearest first. llvmpipe tests the depth before it
// runs a fragment's program and skips the blocks of pixels whose every fragment failed, so a
// surface drawn behind one already there costs its triangles' set-up but not its shading. Fig.
// 11's floor, drawn first, was shaded under every sphere and block as well
// (docs/notes/2026-11-27-lights-fig11.md, "Fig. 11's G-buffer and copy made lighter"). Only the
// cost changes: the depth test keeps the nearest surface
// whatever the order (but for exactly equal depths, where GL_LESS keeps the first drawn).
#pragma once

#include <cstddef>
#include <vector>

#include "sim/scene/Scene.h"
#include "sim/Types.h"

namespace sph::render::solids {

// The distance from `eye` to the nearest point of `shape` (its walls `thickness` m thick; 0 with
// the eye inside), m; +infinity for a plane and a tank, which lie under and around the others
// and go last.
float nearestDistance(const scene::BoundaryShape& shape, float thickness, const Vec3& eye);

// The shapes' indices into `order`, nearest first (ties in the order given); `distance` is
// scratch. Both keep their storage between calls: a still scene allocates nothing.
void frontToBack(const std::vector<scene::BoundaryShape>& shapes, float thickness, const Vec3& eye,
                 std::vector<std::size_t>& order, std::vector<float>& distance);
// The same, returned.
std::vector<std::size_t> frontToBack(const std::vector<scene::BoundaryShape>& shapes,
                                     float thickness, const Vec3& eye);

}  // namespace sph::render::solids
