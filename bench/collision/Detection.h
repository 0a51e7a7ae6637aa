// What bench_collision's recall figures measure: the true pairs of a snapshot (exact), and what
// a CDT configuration or another detector finds on the same positions.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "sim/scene/CollisionDesc.h"
#include "sim/Particles.h"
#include "sim/scene/Scene.h"
#include "sim/cdt/CdtCpu.h"
#include "sim/collision/Detector.h"
#include "sim/collision/Recall.h"

namespace sph::collisionbench {

using collision::IdPair;
using collision::IndexPair;

// Every pair closer than `range`, by id, canonical (sorted, smaller id first).
std::vector<IdPair> truePairs(const Particles& p, float range);

// What the CDT detects on a texture of exactly these positions (everyone searching).
struct CdtDetection {
  collision::Recall recall;
  std::unique_ptr<cdt::CdtCpu> cdt;
  double ms = 0;         // detection step (cdt-cpu)
  double meanRange = 0;  // mean r searched
};

CdtDetection detectCdt(const scene::CollisionDesc& desc,
                       const std::optional<scene::CameraDesc>& camera, const Particles& p,
                       const std::vector<IdPair>& truth);

// What a CPU detector (exact, octree) finds, as recall against `truth`.
collision::Recall detectWith(collision::Detector& detector, const Particles& p, float range,
                             const std::vector<IdPair>& truth);

// The paper's CDT reading: r = 1, one layer, curr_pos from the base texel.
scene::CollisionDesc paperCdt(const scene::Scene& scene);

}  // namespace sph::collisionbench
