// Recall of each method against exact on a snapshot of either density type, and a check that
// cdt-gl finds the same partners as cdt-cpu on the same texture.
#include <cstdio>

#include "bench/collision/Detection.h"
#include "bench/collision/Sections.h"
#include "bench/collision/Snapshot.h"
#include "render/cdt/CdtGl.h"
#include "render/gl/GlContext.h"
#include "sim/collision/Exact.h"
#include "sim/collision/Octree.h"

namespace sph::collisionbench {
namespace {

void printRecallRow(const char* name, const collision::Recall& r, const char* note = "") {
  std::printf("| %s | %.3f | %.3f | %.3f | %.3f | %s |\n", name, r.pairRecall(), r.particleRecall(),
              r.partnerPrecision(), r.unansweredFraction(), note);
}

}  // namespace

void printRecall(const Options& o) {
  std::printf("\n### Recall against exact (snapshot at t = %.2f s, %zu particles)\n\n", o.warm,
              o.recallSize);
  for (char density : {'A', 'B'}) {
    const Snapshot snap = takeSnapshot(density, o.recallSize, o.warm);
    const Particles& p = snap.particles;
    const float range = snap.scene.collision->range;
    const std::vector<IdPair> truth = truePairs(p, range);
    std::printf("Density %c: %zu true pairs closer than %.0f mm.\n\n", density, truth.size(),
                1e3 * range);
    std::printf(
        "| method | pair recall | particle recall | partner precision | one-sided | |\n| --- | "
        "---: | ---: | ---: | ---: | --- |\n");
    collision::ExactDetector exact;
    printRecallRow(enumName(scene::CollisionMethod::Exact), detectWith(exact, p, range, truth),
                   "1 by construction");
    const Vec3 centre = 0.5f * (snap.scene.domain.lo + snap.scene.domain.hi);
    collision::OctreeDetector octree(centre, snap.scene.domain.size().maxCoeff(), 3);
    printRecallRow("octree (depth 3)", detectWith(octree, p, range, truth), "leaf-local search");
    const scene::CollisionDesc paper = paperCdt(snap.scene);
    const CdtDetection cdtPaper = detectCdt(paper, snap.scene.camera, p, truth);
    printRecallRow("cdt, paper (r 1, curr_pos from texel)", cdtPaper.recall);
    scene::CollisionDesc own = paper;
    own.positionSource = scene::CdtPositionSource::Particle;
    printRecallRow("cdt, own position (r 1)", detectCdt(own, snap.scene.camera, p, truth).recall);
    scene::CollisionDesc best = own;
    best.adaptiveTexelRange = true;
    best.maxTexelRange = 4;
    best.layers = 4;
    printRecallRow("cdt, adaptive r + 4 layers",
                   detectCdt(best, snap.scene.camera, p, truth).recall);
    // cdt-gl finds the same partners as cdt-cpu on the same texture: checked, not assumed.
    {
      render::gl::GlContext context = render::gl::GlContext::headless();
      render::cdt::CdtGl gl(cdt::makeSettings(paper, snap.scene.camera));
      Particles q = p;
      for (float& t : q.collideTime) t = -1;
      gl.upload(q);
      gl.step(0.0f, true);  // writes the texture of these positions (detects nothing: empty)
      gl.upload(q);
      gl.step(0.0f, true);  // detects on it
      const std::vector<cdt::Diagnostics> glDiag = gl.diagnostics();
      std::size_t same = 0;
      for (std::size_t i = 0; i < p.size(); ++i)
        same += glDiag[i].partner == cdtPaper.cdt->diagnostics()[i].partner;
      std::printf(
          "| cdt-gl, paper | (= cdt-cpu) | | | | %zu of %zu partners identical to cdt-cpu |\n",
          same, p.size());
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  std::printf(
      "pair recall: true pairs either particle saw in its window; particle recall: particles with "
      "a true\n"
      "partner that chose one; partner precision: chosen partners that are true partners; "
      "one-sided: chosen\n"
      "partners that chose nobody (only one side of the pair reacts, failure mode 2).\n");
}

}  // namespace sph::collisionbench
