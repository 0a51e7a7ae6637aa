// The CPU collision methods against brute force: `exact` finds every pair closer than the range
// (so its recall is 1 by construction), the thesis's octree finds only pairs inside one leaf, and
// the CDT's recall is whatever its texture shows - measured and printed here, and improved by
// the adaptive texel range and depth-peeled layers. Also the particle-system model the paper
// runs (gravity and collisions, no SPH) through the whole Simulation.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "render/cdt/CollisionSetup.h"
#include "sim/run/Simulation.h"
#include "sim/cdt/CdtCpu.h"
#include "sim/collision/Exact.h"
#include "sim/collision/Octree.h"
#include "sim/collision/Recall.h"
#include "tests/CdtTestScenes.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using collision::IdPair;
using collision::IndexPair;
using collision::kNone;

struct Points {
  std::vector<float> x, y, z;
  std::size_t size() const { return x.size(); }
};

Points randomPoints(std::size_t n, float half, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-half, half);
  Points p;
  for (std::size_t i = 0; i < n; ++i)
    p.x.push_back(u(rng)), p.y.push_back(u(rng)), p.z.push_back(u(rng));
  return p;
}

std::vector<IndexPair> bruteForcePairs(const Points& p, float range) {
  std::vector<IndexPair> pairs;
  const double r2 = static_cast<double>(range) * range;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t j = i + 1; j < p.size(); ++j) {
      if (collision::distance2(p.x[i], p.y[i], p.z[i], p.x[j], p.y[j], p.z[j]) < r2)
        pairs.emplace_back(i, j);
    }
  }
  return pairs;
}

TEST(ExactCollision, FindsEveryPairAndTheNearestPartner) {
  const Points p = randomPoints(3000, 0.25f, 1);
  const float range = 0.02f;
  collision::ExactDetector exact;
  std::vector<std::uint32_t> partner;
  std::vector<IndexPair> pairs;
  exact.detect(p.x.data(), p.y.data(), p.z.data(), p.size(), range, nullptr, partner, &pairs);
  const std::vector<IndexPair> truth = bruteForcePairs(p, range);
  ASSERT_GT(truth.size(), 1000u);
  EXPECT_EQ(collision::canonicalPairs(pairs), collision::canonicalPairs(truth));
  // Recall of exact against brute force: 1 by construction.
  std::vector<std::uint32_t> ids(p.size());
  for (std::uint32_t i = 0; i < p.size(); ++i) ids[i] = i;
  const collision::Recall r =
      collision::measureRecall(collision::canonicalPairs(truth), pairs, ids, partner);
  EXPECT_EQ(r.pairRecall(), 1.0);
  EXPECT_EQ(r.particleRecall(), 1.0);
  EXPECT_EQ(r.partnerPrecision(), 1.0);
  EXPECT_EQ(r.unanswered, 0u) << "whoever has a partner is someone's partner in range too";
  // The partner is the nearest (brute force), kNone for the lonely.
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    double best = static_cast<double>(range) * range;
    std::uint32_t nearest = kNone;
    for (std::uint32_t j = 0; j < p.size(); ++j) {
      const double d2 = collision::distance2(p.x[i], p.y[i], p.z[i], p.x[j], p.y[j], p.z[j]);
      if (j != i && (d2 < best || (d2 == best && j < nearest))) best = d2, nearest = j;
    }
    ASSERT_EQ(partner[i], nearest) << i;
  }
  // Particles still cooling down do not search.
  std::vector<std::uint8_t> searching(p.size(), 0);
  exact.detect(p.x.data(), p.y.data(), p.z.data(), p.size(), range, searching.data(), partner,
               nullptr);
  EXPECT_TRUE(
      std::all_of(partner.begin(), partner.end(), [](std::uint32_t j) { return j == kNone; }));
}

TEST(OctreeCollision, FindsPairsInsideALeafOnly) {
  collision::OctreeDetector octree(Vec3::Zero(), 1.0f, 3);
  EXPECT_EQ(octree.nodeCount(), 1u + 8u + 64u + 512u);
  EXPECT_EQ(octree.leafCount(), 512u);
  // The walk from the root agrees with the leaf's index computed directly (edge 1/8).
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 0.4999f);
  std::vector<int> seen(512, 0);
  for (int k = 0; k < 20000; ++k) {
    const float x = u(rng), y = u(rng), z = u(rng);
    const int leaf = octree.leafOf(x, y, z);
    ASSERT_GE(leaf, 0);
    seen[static_cast<std::size_t>(leaf)]++;
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c > 0; }));
  EXPECT_EQ(octree.leafOf(0.6f, 0, 0), -1);
  EXPECT_EQ(octree.leafOf(0.01f, 0.01f, 0.01f), octree.leafOf(0.12f, 0.12f, 0.12f));
  EXPECT_NE(octree.leafOf(0.01f, 0.01f, 0.01f), octree.leafOf(-0.01f, 0.01f, 0.01f));

  // Two points 2 cm apart on either side of the x = 0 face: a true pair the octree misses.
  Points p;
  for (float x : {-0.01f, 0.01f, 0.2f, 0.215f})
    p.x.push_back(x), p.y.push_back(0.05f), p.z.push_back(0.05f);
  std::vector<std::uint32_t> partner;
  std::vector<IndexPair> pairs;
  octree.detect(p.x.data(), p.y.data(), p.z.data(), p.size(), 0.03f, nullptr, partner, &pairs);
  EXPECT_EQ(partner[0], kNone);
  EXPECT_EQ(partner[2], 3u);
  EXPECT_EQ(collision::canonicalPairs(pairs), (std::vector<IdPair>{{2u, 3u}}));

  // On a random cloud: no false pairs, most true ones, never all of them.
  const Points cloud = randomPoints(4000, 0.45f, 4);
  octree.detect(cloud.x.data(), cloud.y.data(), cloud.z.data(), cloud.size(), 0.03f, nullptr,
                partner, &pairs);
  const std::vector<IndexPair> truth = collision::canonicalPairs(bruteForcePairs(cloud, 0.03f));
  const std::vector<IndexPair> found = collision::canonicalPairs(pairs);
  EXPECT_TRUE(std::includes(truth.begin(), truth.end(), found.begin(), found.end()));
  EXPECT_LT(found.size(), truth.size());
  EXPECT_GT(found.size(), truth.size() / 2);
  std::printf("    octree (depth 3, leaf edge 12.5 cm, range 3 cm): pair recall %.3f\n",
              static_cast<double>(found.size()) / static_cast<double>(truth.size()));
}

// The CDT's recall on one texture of the same positions: what its window shows, against exact.
collision::Recall cdtRecall(const scene::CollisionDesc& desc, const Particles& p) {
  cdt::CdtCpu cpu(cdt::makeSettings(desc, std::nullopt));
  cpu.setRecordPairs(true);
  cpu.writeTexture(p.x.data(), p.y.data(), p.z.data(), p.id.data(), p.size());
  Particles q = p;
  for (float& t : q.collideTime) t = -1;  // everyone searches
  cpu.step(q, 0.0f, true);                // dt = 0: detection on exactly these positions
  collision::ExactDetector exact;
  std::vector<std::uint32_t> partner;
  std::vector<IndexPair> pairs;
  exact.detect(p.x.data(), p.y.data(), p.z.data(), p.size(), desc.range, nullptr, partner, &pairs);
  std::vector<IdPair> truth;
  for (const IndexPair& pr : pairs) truth.emplace_back(p.id[pr.first], p.id[pr.second]);
  std::vector<std::uint32_t> chosen(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) chosen[i] = cpu.diagnostics()[i].partner;
  return collision::measureRecall(collision::canonicalPairs(truth), cpu.seenPairs(), p.id, chosen);
}

TEST(CdtRecall, ReportedAndRaisedByTheImprovements) {
  const Particles p = test::randomParticles(20000, 0.5f, 21);
  scene::CollisionDesc paper = test::testCollision();
  paper.positionSource = scene::CdtPositionSource::Particle;
  const collision::Recall base = cdtRecall(paper, p);
  scene::CollisionDesc adaptive = paper;
  adaptive.adaptiveTexelRange = true;
  adaptive.maxTexelRange = 4;
  const collision::Recall withAdaptive = cdtRecall(adaptive, p);
  scene::CollisionDesc layered = paper;
  layered.layers = 4;
  const collision::Recall withLayers = cdtRecall(layered, p);
  scene::CollisionDesc both = adaptive;
  both.layers = 4;
  const collision::Recall withBoth = cdtRecall(both, p);
  std::printf(
      "    cdt pair recall: r=1 %.3f, adaptive r %.3f, 4 layers %.3f, both %.3f (%zu true pairs)\n",
      base.pairRecall(), withAdaptive.pairRecall(), withLayers.pairRecall(), withBoth.pairRecall(),
      base.truePairs);
  EXPECT_GT(base.truePairs, 1000u);
  EXPECT_GT(base.pairRecall(), 0.0);
  EXPECT_LT(base.pairRecall(), 1.0) << "a cloud this deep must hide pairs from one view";
  // Each improvement only widens what a particle sees, so recall cannot drop, and here it rises.
  EXPECT_GT(withAdaptive.pairRecall(), base.pairRecall());
  EXPECT_GT(withLayers.pairRecall(), base.pairRecall());
  EXPECT_GT(withBoth.pairRecall(), std::max(withAdaptive.pairRecall(), withLayers.pairRecall()));
  // Comparing its own position, the CDT never reports a pair that is not one.
  EXPECT_EQ(base.falsePairs, 0u);
  EXPECT_EQ(base.partnerPrecision(), 1.0);
  // The paper's curr_pos from the base texel: another particle's position stands in for its own.
  scene::CollisionDesc texel = paper;
  texel.positionSource = scene::CdtPositionSource::Texel;
  const collision::Recall fromTexel = cdtRecall(texel, p);
  std::printf("    curr_pos from the base texel: partner precision %.3f, pair recall %.3f\n",
              fromTexel.partnerPrecision(), fromTexel.pairRecall());
  EXPECT_LT(fromTexel.partnerPrecision(), 1.0);
}

// The paper's particle system (solver.model = "particles") with each CPU method through the
// whole step: no SPH passes, collisions happen, the run stays finite and inside the domain.
TEST(ParticleModel, RainFallsAndCollidesWithEveryCpuMethod) {
  for (const char* method : {"exact", "octree", "cdt-cpu"}) {
    scene::Scene scene = test::shippedScene(
        "cdt_rain", {"solver.spacing=0.03", std::string("collision.method=") + method,
                     "fluids[0].min=[-0.3,0.62,-0.3]"});
    run::Simulation sim(scene);
    sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
    ASSERT_NE(sim.collisionPass(), nullptr);
    EXPECT_EQ(sim.collisionPass()->name(), method);
    const std::size_t n = sim.fluid().size();
    ASSERT_GT(n, 1000u);
    sim.advanceTo(0.2);
    EXPECT_EQ(sim.profile()[solver::Pass::Density], 0.0) << "no SPH density in the particle model";
    EXPECT_EQ(sim.profile()[solver::Pass::Pressure], 0.0);
    std::size_t cooling = 0;
    for (float t : sim.fluid().collideTime) cooling += t >= 0;
    std::printf("    %s: %zu of %zu particles cooling down after a collision at t = 0.2 s\n",
                method, cooling, n);
    EXPECT_GT(cooling, 0u) << method << ": the rain must hit the sphere and collide";
  }
}

}  // namespace
}  // namespace sph
