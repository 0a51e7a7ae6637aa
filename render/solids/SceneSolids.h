// The opaque solids of a scene, built one way for every command and bench that draws them: its
// boundaries, inside its domain, with walls as thick as the boundary particles' layers.
#pragma once

#include <memory>

#include "render/solids/SolidRenderer.h"
#include "sim/scene/Scene.h"

namespace sph::render::solids {

// Needs a current context.
std::unique_ptr<SolidRenderer> sceneSolids(const scene::Scene& scene);

}  // namespace sph::render::solids
