// The CDT collision pass measured (docs/benchmarks.md, "CDT collision pass"): the thesis's Table
// 4-1 layout (ms per step for 50k-200k particles, density types A and B) for cdt-gl, cdt-cpu,
// exact and octree; the recall of each method against exact; how recall moves with the paper's
// four failure modes; and the improvements that raise it, before and after.
//
// Every figure comes from the shipped rain scenes (scenes/cdt_rain.json = type A,
// scenes/cdt_rain_sparse.json = type B), run as the paper's particle system until the rain has
// hit the sphere (a snapshot at --warm seconds, computed with `exact`); timings restore that
// snapshot and time --steps steps of each method; recall compares what each method detects on the
// snapshot's positions with every pair closer than the collision range.
//
//   OMP_WAIT_POLICY=PASSIVE build/release/bench/bench_collision all > results/collision.md
//   bench_collision table | recall | modes | improvements   (one section)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "bench/collision/Sections.h"
#include "bench/collision/Timing.h"
#include "render/gl/GlContext.h"
#include "sim/Parallel.h"

namespace {

using namespace sph;
using namespace sph::collisionbench;

std::vector<std::size_t> parseSizes(const char* s) {
  std::vector<std::size_t> out;
  for (const char* p = s; *p;) {
    out.push_back(std::strtoull(p, nullptr, 10));
    p = std::strchr(p, ',');
    if (!p) break;
    ++p;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: bench_collision all|table|recall|modes|improvements [--sizes N,N] "
                 "[--steps N] [--warm S] [--size N] [--csv FILE]\n");
    return 2;
  }
  const std::string what = argv[1];
  Options o;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--sizes")
      o.sizes = parseSizes(argv[i + 1]);
    else if (key == "--steps")
      o.steps = std::atoi(argv[i + 1]);
    else if (key == "--warm")
      o.warm = std::atof(argv[i + 1]);
    else if (key == "--size")
      o.recallSize = std::strtoull(argv[i + 1], nullptr, 10);
    else if (key == "--csv")
      o.csv = argv[i + 1];
    else {
      std::fprintf(stderr, "bench_collision: unknown option %s\n", key.c_str());
      return 2;
    }
  }
  try {
    {
      render::gl::GlContext probe = render::gl::GlContext::headless();
      std::printf("cdt-gl on %s (%s); %d OpenMP threads; load average %.2f at the start\n",
                  probe.info().renderer.c_str(), probe.info().version.c_str(), threadCount(),
                  loadAverage());
    }
    if (what == "table" || what == "all") printTable(o);
    if (what == "recall" || what == "all") printRecall(o);
    if (what == "modes" || what == "all") printModes(o);
    if (what == "improvements" || what == "all") printImprovements(o);
    std::printf("\nload average %.2f at the end\n", loadAverage());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_collision: %s\n", e.what());
    return 1;
  }
  return 0;
}
