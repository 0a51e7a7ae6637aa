#include "render/cdt/CollisionSetup.h"

#include <sstream>

#include "render/cdt/CdtGlPass.h"
#include "render/gl/GlError.h"
#include "sim/InputError.h"
#include "sim/cdt/CdtCpu.h"
#include "sim/collision/Exact.h"
#include "sim/collision/Octree.h"

namespace sph::render::cdt {
std::unique_ptr<CollisionPass> makeCollisionPass(const scene::Scene& scene) {
  if (!scene.collision || scene.collision->method == scene::CollisionMethod::None) return nullptr;
  const scene::CollisionDesc& c = *scene.collision;
  // Checked by the loader too, but `run --end` may have moved the end time since.
  sph::cdt::requireIdsInRange(scene);
  switch (c.method) {
    case scene::CollisionMethod::None:
      return nullptr;
    case scene::CollisionMethod::Exact:
      return std::make_unique<collision::DetectorPass>(std::make_unique<collision::ExactDetector>(),
                                                       c);
    case scene::CollisionMethod::Octree: {
      // The thesis's root is a fixed cube around the scene (50^3 units); ours defaults to the
      // cube around the domain.
      const Vec3 centre = 0.5f * (scene.domain.lo + scene.domain.hi);
      const float size = c.octreeRootSize > 0 ? c.octreeRootSize : scene.domain.size().maxCoeff();
      return std::make_unique<collision::DetectorPass>(
          std::make_unique<collision::OctreeDetector>(centre, size, c.octreeDepth), c);
    }
    case scene::CollisionMethod::CdtCpu:
      return std::make_unique<sph::cdt::CdtCpuPass>(sph::cdt::makeSettings(c, scene.camera));
    case scene::CollisionMethod::CdtGl:
      try {
        return std::make_unique<CdtGlPass>(sph::cdt::makeSettings(c, scene.camera));
      } catch (const gl::GlError& e) {
        throw InputError(scene.sourcePath +
                         ": collision.method: cdt-gl is unavailable: " + e.what() +
                         "; \"method\": \"cdt-cpu\" runs the same algorithm on the CPU (--set "
                         "collision.method=cdt-cpu)");
      }
  }
  return nullptr;
}

std::string describeCollision(const scene::Scene& scene) {
  if (!scene.collision) return "none (no collision section)";
  const scene::CollisionDesc& c = *scene.collision;
  std::ostringstream s;
  s << enumName(c.method);
  if (c.method == scene::CollisionMethod::None) return s.str();
  s << ", range " << c.range << " m, response " << enumName(c.response);
  if (c.method == scene::CollisionMethod::CdtCpu || c.method == scene::CollisionMethod::CdtGl) {
    s << ", texture " << c.resolution[0] << "x" << c.resolution[1] << " x " << c.layers << " layer"
      << (c.layers == 1 ? "" : "s") << ", r "
      << (c.adaptiveTexelRange ? "adaptive" : std::to_string(c.texelRange));
    s << (c.method == scene::CollisionMethod::CdtGl ? ", GL context: headless EGL"
                                                    : ", no GL context");
  } else if (c.method == scene::CollisionMethod::Octree) {
    s << ", depth " << c.octreeDepth;
  }
  return s.str();
}

}  // namespace sph::render::cdt
