#include "bench/collision/Detection.h"

#include "bench/collision/Timing.h"
#include "sim/collision/Exact.h"

namespace sph::collisionbench {

std::vector<IdPair> truePairs(const Particles& p, float range) {
  collision::ExactDetector exact;
  std::vector<std::uint32_t> partner;
  std::vector<IndexPair> pairs;
  exact.detect(p.x.data(), p.y.data(), p.z.data(), p.size(), range, nullptr, partner, &pairs);
  std::vector<IdPair> ids;
  ids.reserve(pairs.size());
  for (const IndexPair& q : pairs) ids.emplace_back(p.id[q.first], p.id[q.second]);
  return collision::canonicalPairs(ids);
}

CdtDetection detectCdt(const scene::CollisionDesc& desc,
                       const std::optional<scene::CameraDesc>& camera, const Particles& p,
                       const std::vector<IdPair>& truth) {
  CdtDetection d;
  d.cdt = std::make_unique<cdt::CdtCpu>(cdt::makeSettings(desc, camera));
  d.cdt->setRecordPairs(true);
  d.cdt->writeTexture(p.x.data(), p.y.data(), p.z.data(), p.id.data(), p.size());
  Particles q = p;
  for (float& t : q.collideTime) t = -1;
  const auto start = Clock::now();
  d.cdt->step(q, 0.0f, true);
  d.ms = millisecondsSince(start);
  std::vector<std::uint32_t> chosen(p.size());
  double r = 0;
  std::size_t searching = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const cdt::Diagnostics& diag = d.cdt->diagnostics()[i];
    chosen[i] = diag.partner;
    if (diag.texelRange > 0) r += diag.texelRange, ++searching;
  }
  d.meanRange = searching ? r / static_cast<double>(searching) : 0;
  d.recall = collision::measureRecall(truth, d.cdt->seenPairs(), p.id, chosen);
  return d;
}

collision::Recall detectWith(collision::Detector& detector, const Particles& p, float range,
                             const std::vector<IdPair>& truth) {
  std::vector<std::uint32_t> partner;
  std::vector<IndexPair> pairs;
  detector.detect(p.x.data(), p.y.data(), p.z.data(), p.size(), range, nullptr, partner, &pairs);
  std::vector<IdPair> seen;
  for (const IndexPair& q : pairs) seen.emplace_back(p.id[q.first], p.id[q.second]);
  std::vector<std::uint32_t> chosen(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    chosen[i] = partner[i] == collision::kNone ? collision::kNone : p.id[partner[i]];
  return collision::measureRecall(truth, seen, p.id, chosen);
}

scene::CollisionDesc paperCdt(const scene::Scene& scene) {
  scene::CollisionDesc d = *scene.collision;
  d.method = scene::CollisionMethod::CdtCpu;
  d.texelRange = 1;
  d.layers = 1;
  d.adaptiveTexelRange = false;
  d.positionSource = scene::CdtPositionSource::Texel;
  return d;
}
}  // namespace sph::collisionbench
