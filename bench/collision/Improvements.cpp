// Our improvements to the CDT (adaptive texel range, depth-peeled layers, own position), each
// with recall and the time of cdt-cpu and cdt-gl; --csv writes the rows for plot_sweep.py (run
// time against error of the collision pass).
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/collision/Detection.h"
#include "bench/collision/Sections.h"
#include "bench/collision/Timing.h"
#include "sim/Parallel.h"
#include "sim/collision/Exact.h"
#include "sim/collision/Octree.h"

namespace sph::collisionbench {

void printImprovements(const Options& o) {
  std::printf("\n### Improvements (density A, %zu particles, snapshot at t = %.2f s)\n\n",
              o.recallSize, o.warm);
  const Snapshot snap = takeSnapshot('A', o.recallSize, o.warm);
  const Particles& p = snap.particles;
  const float range = snap.scene.collision->range;
  const std::vector<IdPair> truth = truePairs(p, range);
  std::printf(
      "| variant | pair recall | particle recall | one-sided | cdt-cpu ms (least / median) | "
      "cdt-gl ms "
      "|\n| --- | ---: | ---: | ---: | ---: | ---: |\n");
  // Run time against error for the collision pass (docs/benchmarks.md, "Run time vs error:
  // collision"): one row per method and option set, the miss rate (1 - pair recall) against the
  // least cdt-cpu / method ms, for plot_sweep.py.
  FILE* csv = o.csv.empty() ? nullptr : std::fopen(o.csv.c_str(), "w");
  if (!o.csv.empty() && !csv) throw std::runtime_error("cannot write " + o.csv);
  if (csv)
    std::fprintf(csv,
                 "variant,method,options,status,threads,pair_recall,particle_recall,miss_rate,ms_"
                 "least,ms_median\n");
  int row = 0;
  auto csvRow = [&](const char* method, const char* options, const collision::Recall& r,
                    const Timing& t) {
    if (csv)
      std::fprintf(csv, "%d,%s,\"%s\",stable,%d,%.4f,%.4f,%.4f,%.3f,%.3f\n", ++row, method, options,
                   threadCount(), r.pairRecall(), r.particleRecall(), 1.0 - r.pairRecall(), t.minMs,
                   t.medianMs);
  };
  {  // the baselines: exact is 1 by construction, the octree misses pairs across leaf faces
    collision::ExactDetector exact;
    const collision::Recall re = detectWith(exact, p, range, truth);
    const Timing te = timeMethod(snap, scene::CollisionMethod::Exact, o.steps);
    std::printf("| exact | %.3f | %.3f | %.3f | %s (exact) | - |\n", re.pairRecall(),
                re.particleRecall(), re.unansweredFraction(), format(te).c_str());
    csvRow(enumName(scene::CollisionMethod::Exact), "", re, te);
    const Vec3 centre = 0.5f * (snap.scene.domain.lo + snap.scene.domain.hi);
    collision::OctreeDetector octree(centre, snap.scene.domain.size().maxCoeff(), 3);
    const collision::Recall ro = detectWith(octree, p, range, truth);
    const Timing to = timeMethod(snap, scene::CollisionMethod::Octree, std::max(2, o.steps / 3));
    std::printf("| octree (depth 3) | %.3f | %.3f | %.3f | %s (octree) | - |\n", ro.pairRecall(),
                ro.particleRecall(), ro.unansweredFraction(), format(to).c_str());
    csvRow(enumName(scene::CollisionMethod::Octree), "depth 3", ro, to);
  }
  struct Variant {
    const char* name;
    bool particle, adaptive;
    int layers;
    std::vector<std::string> keys;
  };
  const std::vector<Variant> variants = {
      {"paper: r 1, curr_pos from texel, 1 layer", false, false, 1, {}},
      {"own position (ours, default)", true, false, 1, {"collision.position_source=particle"}},
      {"+ adaptive r (cap 4)",
       true,
       true,
       1,
       {"collision.position_source=particle", "collision.adaptive_texel_range=true"}},
      {"+ 2 layers", true, false, 2, {"collision.position_source=particle", "collision.layers=2"}},
      {"+ 4 layers", true, false, 4, {"collision.position_source=particle", "collision.layers=4"}},
      {"+ adaptive r + 2 layers",
       true,
       true,
       2,
       {"collision.position_source=particle", "collision.adaptive_texel_range=true",
        "collision.layers=2"}},
      {"+ adaptive r + 4 layers",
       true,
       true,
       4,
       {"collision.position_source=particle", "collision.adaptive_texel_range=true",
        "collision.layers=4"}},
  };
  for (const Variant& v : variants) {
    scene::CollisionDesc d = paperCdt(snap.scene);
    if (v.particle) d.positionSource = scene::CdtPositionSource::Particle;
    d.adaptiveTexelRange = v.adaptive;
    d.maxTexelRange = 4;
    d.layers = v.layers;
    const CdtDetection det = detectCdt(d, snap.scene.camera, p, truth);
    const Timing cpu = timeMethod(snap, scene::CollisionMethod::CdtCpu, o.steps, v.keys);
    const Timing gl = timeMethod(snap, scene::CollisionMethod::CdtGl, o.steps, v.keys);
    std::printf("| %s | %.3f | %.3f | %.3f | %s | %s |\n", v.name, det.recall.pairRecall(),
                det.recall.particleRecall(), det.recall.unansweredFraction(), format(cpu).c_str(),
                format(gl).c_str());
    csvRow(enumName(scene::CollisionMethod::CdtCpu), v.name, det.recall, cpu);
    csvRow(enumName(scene::CollisionMethod::CdtGl), v.name, det.recall, gl);
    std::fflush(stdout);
  }
  if (csv) std::fclose(csv);
}

}  // namespace sph::collisionbench
