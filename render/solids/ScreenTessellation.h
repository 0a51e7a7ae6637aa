// How finely the round solids (sphere, cup) are tessellated: for their size on screen, from a
// bound on how far the mesh may lie from the true surface, in pixels (docs/lights.md,
// "Solids tessellated for their size on screen"). On llvmpipe a triangle costs its set-up
// whatever its size: Fig. 11's 36 spheres at a fixed 64 segments were 143,042 mostly pixel-sized
// triangles and most of the deferred G-buffer pass (docs/notes/2026-11-27-lights-fig11.md,
// "the solids tessellated for their size on screen").
//
// The rule. A sphere of n segments around its equator (n / 2 rings) has flat faces of 2 pi / n
// by 2 pi / n; the middle of an equator face lies r (1 - cos^2(pi / n)) = r sin^2(pi / n) inside
// the sphere, twice a polygon's sagitta r (1 - cos(pi / n)), and the outline seen from any side
// runs through such faces' diagonals. A cup's walls and rims (circles of n segments) lie at most
// the sagitta inside. We bound the larger of the two:
//     r_px sin^2(pi / n) <= pixels
// where r_px is the radius on screen in pixels: the shape's radius times the projection's scale
// f / w at the depth w of the shape's nearest point (its bounding sphere's), widened by
// 1 / cos of its centre's angle off the view axis (lengths across the ray project so much larger
// towards the frame's corners). n is the smallest multiple of 4 that meets the bound, within
// [floor, cap]: a shape outside the view gets the floor, one that reaches the eye's plane the cap.
// Multiples of 4 keep a moving camera from re-tessellating for every pixel of change.
#pragma once

#include "sim/scene/Camera.h"
#include "sim/scene/Scene.h"

namespace sph::render::solids {

struct TessellationBound {
  float pixels = 0.5f;  // px, the largest distance from the mesh to the true surface on screen
  int floor = 8;        // segments at least (a sphere of 4 rings)
  int cap = 128;        // segments at most (a sphere filling a 1,080-line frame needs ~100)
};

// The segments for a circle or sphere of `radiusPixels` (px on screen) under `bound`.
int segmentsFor(float radiusPixels, const TessellationBound& bound);

// The radius on screen (px) of a length `radius` (m) at the nearest point of the bounding sphere
// (centre, boundRadius) seen through `projView` (sim/scene/Camera.h's perspective) in a viewport of
// width x height px: 0 outside the frustum, +infinity where the sphere reaches the eye's plane.
float radiusOnScreen(const scene::Mat4& projView, int width, int height, const Vec3& centre,
                     float boundRadius, float radius);

// The segments for `shape` (walls `thickness` m thick) seen through projView in width x height
// px; 0 for the shapes with no curve (tank, block, plane), whose mesh does not depend on it.
int screenSegments(const scene::BoundaryShape& shape, float thickness, const scene::Mat4& projView,
                   int width, int height, const TessellationBound& bound);

}  // namespace sph::render::solids
