// The walls and containers of a scene in its pictures, as its render section asks
// (render.solids): translucent boundary particles, lit opaque surfaces, or none. One place for
// every command that draws (`run` with a render section, `render`, `view`).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "render/solids/SolidRenderer.h"
#include "render/splat/FrameRenderer.h"
#include "sim/scene/Scene.h"

namespace sph::render::solids {

// Boundary particle positions x, y, z (m), asked for only when the points are drawn.
using BoundaryPositions = std::function<std::array<std::vector<float>, 3>()>;

// Sets up `renderer` to draw the walls of `scene`. The returned renderer of opaque solids (null
// otherwise) is a layer of `renderer`: keep it alive while `renderer` draws. Needs a current
// context.
std::unique_ptr<SolidRenderer> showSolids(const scene::Scene& scene, splat::FrameRenderer& renderer,
                                          const BoundaryPositions& boundary);

}  // namespace sph::render::solids
