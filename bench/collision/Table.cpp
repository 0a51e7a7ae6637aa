// The thesis's Table 4-1 layout: ms per step of each method for 50k-200k particles of density
// types A and B, next to the thesis's figures (seed 001, Tables 4-1 and 5-1).
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include "bench/collision/Sections.h"
#include "bench/collision/Timing.h"

namespace sph::collisionbench {

void printTable(const Options& o) {
  // Seed 001: Table 4-1 (CDT, bunny, RTX 2060) and Table 5-1 (depth-3 octree, bunny).
  const std::map<std::size_t, std::array<double, 3>> paper = {{50000, {12, 13, 100}},
                                                              {100000, {27, 31, 195}},
                                                              {150000, {52, 50, 284}},
                                                              {125000, {46.75, 46.75, NAN}},
                                                              {200000, {65, 70, 413}}};
  const int octreeSteps = std::max(2, o.steps / 3);
  std::printf("\n### Table 4-1 layout: ms per step (least / median)\n\n");
  std::printf(
      "| density | particles | cdt-gl pass | cdt-gl resident | resident, raster write | cdt-cpu | "
      "exact | octree |");
  std::printf(" thesis CDT (RTX 2060) | thesis octree |\n");
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (char density : {'A', 'B'}) {
    for (std::size_t n : o.sizes) {
      const Snapshot snap = takeSnapshot(density, n, o.warm);
      const Timing gl = timeMethod(snap, scene::CollisionMethod::CdtGl, o.steps);
      const Timing resident = timeGlResident(snap, o.steps);
      const Timing raster = timeGlResident(snap, o.steps, true);
      const Timing cpu = timeMethod(snap, scene::CollisionMethod::CdtCpu, o.steps);
      const Timing exact = timeMethod(snap, scene::CollisionMethod::Exact, o.steps);
      const Timing octree = timeMethod(snap, scene::CollisionMethod::Octree, octreeSteps);
      const auto p = paper.count(n) ? paper.at(n) : std::array<double, 3>{NAN, NAN, NAN};
      auto figure = [](double v) {
        char text[32];
        std::snprintf(text, sizeof text,
                      std::isnan(v)        ? "-"
                      : v == std::floor(v) ? "%.0f"
                                           : "%.2f",
                      v);
        return std::string(text);
      };
      std::printf("| %c | %zu | %s | %s | %s | %s | %s | %s | %s | %s |\n", density,
                  snap.particles.size(), format(gl).c_str(), format(resident).c_str(),
                  format(raster).c_str(), format(cpu).c_str(), format(exact).c_str(),
                  format(octree, 0).c_str(), figure(density == 'A' ? p[0] : p[1]).c_str(),
                  figure(p[2]).c_str());
      std::fflush(stdout);
    }
  }
  std::printf(
      "\nLeast / median ms over %d steps (octree: %d) of the collide pass. cdt-gl pass: inside "
      "the\n"
      "particle-system step (upload, one draw with transform feedback, the compute-shader texture\n"
      "write, read back); cdt-gl resident: the same draw and write with the state kept on the GPU\n"
      "between steps, as the paper runs it; raster write: the same with the paper's texture write\n"
      "(rasterised points, depth test). cdt-gl runs on Mesa llvmpipe (the CPU), not a GPU.\n"
      "The thesis's figures: Table 4-1 (bunny), its 46.75 ms average for 125,000 particles, and\n"
      "Table 5-1 (depth-3 octree, bunny).\n",
      o.steps, octreeSteps);
}

}  // namespace sph::collisionbench
