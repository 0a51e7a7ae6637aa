#include "render/solids/SceneSolids.h"

#include "sim/solver/SceneSetup.h"

namespace sph::render::solids {

std::unique_ptr<SolidRenderer> showSolids(const scene::Scene& scene, splat::FrameRenderer& renderer,
                                          const BoundaryPositions& boundary) {
  switch (renderer.desc().solids) {
    case scene::RenderSolids::None:
      return nullptr;
    case scene::RenderSolids::Points: {
      const auto b = boundary();
      renderer.setBoundary(b[0], b[1], b[2]);
      return nullptr;
    }
    case scene::RenderSolids::Opaque: {
      // The walls as thick as the boundary particles' layers (sim/scene/Solid.h has them so).
      const float thickness = scene.solver.wallThickness();
      auto solids = std::make_unique<SolidRenderer>(scene.boundaries, scene.domain, thickness);
      renderer.setLayers({solids.get()});
      return solids;
    }
  }
  return nullptr;
}

}  // namespace sph::render::solids
