#include "render/solids/SceneSolids.h"

#include "sim/solver/SceneSetup.h"

namespace sph::render::solids {

std::unique_ptr<SolidRenderer> sceneSolids(const scene::Scene& scene) {
  // sim/scene/Solid.h gives the walls the boundary particles' layers as their thickness.
  const float thickness = scene.solver.wallThickness();
  return std::make_unique<SolidRenderer>(scene.boundaries, scene.domain, thickness);
}

}  // namespace sph::render::solids
