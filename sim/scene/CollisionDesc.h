// The scene's `collision` section as the simulator sees it (docs/scene-format.md, "collision"):
// which inter-particle collision method runs after the integration, and the parameters of the
// CDT algorithm of seeds 000/001 with our improvements as switchable options. Validated by the
// loader; every field documents its unit.
#pragma once

#include <array>

#include "sim/scene/CameraDesc.h"
#include "sim/scene/EnumNames.h"

namespace sph::scene {

enum class CollisionMethod {
  None,    // section present, pass off (handy with --set collision.method=none)
  Exact,   // every pair within range, neighbour grid (ground truth for recall)
  Octree,  // the thesis's depth-3 octree, leaf-local search (seed 001, section 5)
  CdtCpu,  // the CDT algorithm on the CPU: the reference of cdt-gl
  CdtGl,   // the CDT algorithm in GLSL, transform feedback (seed 000, section 3)
};
// Scene key collision.method (sim/scene/EnumNames.h).
constexpr const char* nameOf(CollisionMethod v) {
  switch (v) {
    case CollisionMethod::None:
      return "none";
    case CollisionMethod::Exact:
      return "exact";
    case CollisionMethod::Octree:
      return "octree";
    case CollisionMethod::CdtCpu:
      return "cdt-cpu";
    case CollisionMethod::CdtGl:
      return "cdt-gl";
  }
  return nullptr;
}

enum class CollisionResponse {
  // Our default for SPH: push the particle out to `range` from its partner (half the overlap,
  // the partner does the other half) and remove the velocity towards it.
  Separate,
  // Seed 000, section 3.2, lines 20-30: speed x speed_factor, direction away from the partner,
  // cooldown; the uncollided particle integrates.
  Paper,
};
// Scene key collision.response.
constexpr const char* nameOf(CollisionResponse v) {
  switch (v) {
    case CollisionResponse::Separate:
      return "separate";
    case CollisionResponse::Paper:
      return "paper";
  }
  return nullptr;
}

enum class CdtCameraMode {
  Render,  // collision camera = render camera (the paper's measurements)
  Fixed,   // its own pose (`collision.pose`)
  Offset,  // render camera moved by `offset` along its own z axis (seed 000, eq. 1)
};
// Scene key collision.camera.
constexpr const char* nameOf(CdtCameraMode v) {
  switch (v) {
    case CdtCameraMode::Render:
      return "render";
    case CdtCameraMode::Fixed:
      return "fixed";
    case CdtCameraMode::Offset:
      return "offset";
  }
  return nullptr;
}

// Which position a particle compares with the texture (DESIGN.md, "three spots").
enum class CdtPositionSource {
  Particle,  // its own position (ours)
  Texel,     // curr_pos read from its base texel, as in the pseudo-code line 5 (may be another's)
};
// Scene key collision.position_source.
constexpr const char* nameOf(CdtPositionSource v) {
  switch (v) {
    case CdtPositionSource::Particle:
      return "particle";
    case CdtPositionSource::Texel:
      return "texel";
  }
  return nullptr;
}

// How cdt-gl fills the texture (cdt-cpu has one way; all three give the same texture).
enum class CdtTextureWrite {
  Atomic,  // a compute shader keeps the nearest per texel with atomic minima (ours: fast on
           // llvmpipe)
  Raster,  // points rasterised by the collision camera, depth test keeps the nearest (the paper's)
};

struct CollisionDesc {
  CollisionMethod method = CollisionMethod::CdtCpu;
  float range = 0;  // m, collision_range: pairs closer than this collide (> 0 after loading)
  CollisionResponse response = CollisionResponse::Separate;
  float speedFactor = 0.2f;  // paper response: speed multiplier (the pseudo-code's 0.2)
  float cooldown = 0;        // s, a_CollideTime after a collision (g_collision_time); 0 = none
  CdtPositionSource positionSource = CdtPositionSource::Particle;

  // CDT parameters.
  std::array<int, 2> resolution = {500, 500};  // texels, width x height
  int texelRange = 1;                          // texel_collide_range r: (2r+1)^2 texels searched
  bool adaptiveTexelRange = false;  // improvement: r from the projected range, per particle
  int maxTexelRange = 4;            // cap of the adaptive r
  int layers = 1;                   // improvement: depth-peeled layers (1 = the paper)
  CdtTextureWrite textureWrite = CdtTextureWrite::Atomic;  // cdt-gl only
  CdtCameraMode camera = CdtCameraMode::Render;
  float offset = 0;  // m, eq. 1 (offset mode)
  CameraDesc pose;   // fixed mode
  bool hasPose = false;

  // Octree parameters (seed 001, section 5).
  int octreeDepth = 3;
  float octreeRootSize = 0;  // m, edge of the cubic root; 0 = the domain's largest edge
};

}  // namespace sph::scene
