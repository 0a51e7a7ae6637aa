// The surface mesh (`sphsplat mesh`, render/mesh) measured: time per frame from particles to a
// mesh (density field + lattice + vertices with normals + triangles, without the file write), the
// mesh's size, and whether it is closed, at 100k and 1M particles. The particles are a splash
// stand-in we can make at any size: a pool on the rest lattice, a ball falling into it and a
// spray of small clumps and loose drops (jittered, fixed seed), the same shape at every count.
//   build/release/bench/bench_mesh [--counts 100000,1000000] [--cell 0.5] [--repeat 3]
// Prints one row per count (minimum time of the repeats; the phases are those of that run).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "render/mesh/SurfaceMesh.h"
#include "render/splat/SplatBuilder.h"
#include "sim/Parallel.h"

using namespace sph;

namespace {

struct Cloud {
  std::vector<float> x, y, z;
  void add(float a, float b, float c) { x.push_back(a), y.push_back(b), z.push_back(c); }
};

// About n particles at spacing s = cbrt(volume / n) in a 1 x 0.5 x 0.5 m box: a pool 0.2 m deep,
// a ball of radius 0.1 m above it, 200 clumps of up to 3 spacings and 2000 single drops.
Cloud splash(std::size_t n, float& spacing) {
  const double ballRadius = 0.1;
  const double volume = 1.0 * 0.2 * 0.5 + 4.0 / 3.0 * 3.14159265 * std::pow(ballRadius, 3);
  spacing = static_cast<float>(std::cbrt(volume / static_cast<double>(n)));
  const float s = spacing;
  std::mt19937 random(12345);
  std::uniform_real_distribution<float> u(0, 1);
  auto jitter = [&] { return 0.05f * s * (u(random) - 0.5f); };
  Cloud c;
  const int nx = static_cast<int>(1.0f / s), ny = static_cast<int>(0.2f / s),
            nz = static_cast<int>(0.5f / s);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        c.add((i + 0.5f) * s + jitter(), (j + 0.5f) * s + jitter(), (k + 0.5f) * s + jitter());
  const float r = static_cast<float>(ballRadius);
  const int nb = static_cast<int>(r / s);
  for (int k = -nb; k <= nb; ++k)
    for (int j = -nb; j <= nb; ++j)
      for (int i = -nb; i <= nb; ++i) {
        const float dx = i * s, dy = j * s, dz = k * s;
        if (dx * dx + dy * dy + dz * dz <= r * r)
          c.add(0.5f + dx + jitter(), 0.33f + dy + jitter(), 0.25f + dz + jitter());
      }
  for (int clump = 0; clump < 200; ++clump) {
    const float cx = u(random), cy = 0.2f + 0.25f * u(random), cz = 0.5f * u(random);
    const int m = 2 + static_cast<int>(3 * u(random));
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i)
          c.add(cx + i * s + jitter(), cy + j * s + jitter(), cz + k * s + jitter());
  }
  for (int drop = 0; drop < 2000; ++drop)
    c.add(u(random), 0.2f + 0.3f * u(random), 0.5f * u(random));
  return c;
}

std::vector<std::size_t> parseCounts(const char* text) {
  std::vector<std::size_t> counts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) counts.push_back(std::stoull(item));
  return counts;
}

double seconds(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> counts = {100000, 1000000};
  float cell = 0.5f;
  int repeat = 3;
  for (int a = 1; a + 1 < argc; a += 2) {
    if (!std::strcmp(argv[a], "--counts"))
      counts = parseCounts(argv[a + 1]);
    else if (!std::strcmp(argv[a], "--cell"))
      cell = std::stof(argv[a + 1]);
    else if (!std::strcmp(argv[a], "--repeat"))
      repeat = std::max(1, std::atoi(argv[a + 1]));
    else {
      std::fprintf(stderr, "usage: bench_mesh [--counts N,N] [--cell SPACINGS] [--repeat R]\n");
      return 2;
    }
  }
  std::printf("threads %d, cell %g spacings, kernel radius 2.5 spacings, min of %d runs\n",
              threadCount(), cell, repeat);
  std::printf("%10s %8s %9s %9s %9s %9s %9s %10s %10s %8s %8s %6s %8s\n", "particles", "spacing",
              "field_ms", "lattice", "vertices", "triangles", "total_ms", "triangles", "vertices",
              "blocks", "surface", "closed", "Euler");
  for (const std::size_t n : counts) {
    float spacing = 0;
    const Cloud c = splash(n, spacing);
    double best = 1e30, bestField = 0;
    render::mesh::MeshStats bestStats;
    render::mesh::SurfaceMesh mesh;
    for (int r = 0; r < repeat; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      const render::splat::DensityField field(c.x.data(), c.y.data(), c.z.data(), c.x.size(),
                                              spacing, 2.5f);
      const double fieldSeconds = seconds(t0);
      const float SD = render::splat::surfaceDensity(field, 0);
      render::mesh::MeshStats stats;
      mesh = render::mesh::extractSurface(field, SD, cell * spacing, &stats);
      const double total = seconds(t0);
      if (total < best) best = total, bestField = fieldSeconds, bestStats = stats;
    }
    const render::mesh::MeshCheck check = render::mesh::checkEdges(mesh);
    const long long euler = static_cast<long long>(mesh.vertexCount()) -
                            static_cast<long long>(check.edges) +
                            static_cast<long long>(mesh.triangleCount());
    std::printf("%10zu %8.5f %9.1f %9.1f %9.1f %9.1f %9.1f %10zu %10zu %8zu %8zu %6s %8lld\n",
                c.x.size(), spacing, 1e3 * bestField, 1e3 * bestStats.timings.lattice,
                1e3 * bestStats.timings.vertices, 1e3 * bestStats.timings.triangles, 1e3 * best,
                mesh.triangleCount(), mesh.vertexCount(), bestStats.blocks, bestStats.surfaceBlocks,
                check.watertight() && check.misorientedEdges == 0 ? "yes" : "NO", euler);
    std::fflush(stdout);
  }
  return 0;
}
