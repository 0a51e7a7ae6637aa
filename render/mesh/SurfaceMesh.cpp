#include "render/mesh/SurfaceMesh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "render/mesh/CaseTable.h"
#include "sim/InputError.h"
#include "sim/Parallel.h"

namespace sph::render::mesh {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

constexpr int kBlockBits = 3, kBlock = 1 << kBlockBits, kBlockPoints = kBlock * kBlock * kBlock;
constexpr std::size_t kMaxBlocks = std::size_t{1} << 26;         // the block index: 256 MB
constexpr std::size_t kMaxLatticePoints = std::size_t{1} << 31;  // D at them: 8 GB

int localPoint(int i, int j, int k) {
  return (i & (kBlock - 1)) + kBlock * ((j & (kBlock - 1)) + kBlock * (k & (kBlock - 1)));
}

// The sparse lattice: point (i, j, k) at origin + cell (i, j, k); blocks of 8^3 points, those
// that exist listed in increasing linear order (slot), the others read D = 0.
struct Lattice {
  double origin[3] = {0, 0, 0};
  double cell = 0;
  int blocks[3] = {0, 0, 0};
  std::vector<std::int32_t> slotOf;         // per block of the box, -1 when absent
  std::vector<std::array<int, 3>> blockAt;  // per slot
  std::vector<float> values;                // per slot, kBlockPoints

  std::int32_t slot(int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0) return -1;
    const int bi = i >> kBlockBits, bj = j >> kBlockBits, bk = k >> kBlockBits;
    if (bi >= blocks[0] || bj >= blocks[1] || bk >= blocks[2]) return -1;
    return slotOf[static_cast<std::size_t>(bi) +
                  static_cast<std::size_t>(blocks[0]) *
                      (static_cast<std::size_t>(bj) + static_cast<std::size_t>(blocks[1]) * bk)];
  }
  float value(int i, int j, int k) const {
    const std::int32_t s = slot(i, j, k);
    return s < 0 ? 0.0f : values[static_cast<std::size_t>(s) * kBlockPoints + localPoint(i, j, k)];
  }
  Vec3 position(double i, double j, double k) const {
    return Vec3(static_cast<float>(origin[0] + cell * i), static_cast<float>(origin[1] + cell * j),
                static_cast<float>(origin[2] + cell * k));
  }
};

Lattice buildLattice(const splat::DensityField& field, float cellSize) {
  Lattice L;
  L.cell = cellSize;
  const std::vector<float>* xyz[3] = {&field.sortedX(), &field.sortedY(), &field.sortedZ()};
  const double margin = field.kernelRadius() + cellSize;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const auto [mn, mx] = std::minmax_element(xyz[a]->begin(), xyz[a]->end());
    lo[a] = *mn, hi[a] = *mx;
    L.origin[a] = lo[a] - margin;
    const double points = std::ceil((hi[a] - lo[a] + 2 * margin) / cellSize) + 1;
    L.blocks[a] = static_cast<int>(std::min(points / kBlock + 1, 1e9));
  }
  const double total = static_cast<double>(L.blocks[0]) * L.blocks[1] * L.blocks[2];
  if (total > static_cast<double>(kMaxBlocks)) {
    throw InputError("the particles span " + number(hi[0] - lo[0]) + " x " + number(hi[1] - lo[1]) +
                     " x " + number(hi[2] - lo[2]) + " m, too many cells of " + number(cellSize) +
                     " m for the mesh's block index; give a larger --cell");
  }
  L.slotOf.assign(static_cast<std::size_t>(total), 0);
  // Mark the blocks within `margin` of each grid cell's particles (their tight box).
  const grid::NeighbourGrid& grid = field.grid();
  for (std::size_t c = 0; c < grid.cellCount(); ++c) {
    const std::uint32_t b = grid.cellBegin(c), e = grid.cellEnd(c);
    if (b == e) continue;
    int from[3], to[3];
    for (int a = 0; a < 3; ++a) {
      const auto [mn, mx] = std::minmax_element(xyz[a]->begin() + b, xyz[a]->begin() + e);
      const double p0 = (*mn - margin - L.origin[a]) / cellSize;
      const double p1 = (*mx + margin - L.origin[a]) / cellSize;
      from[a] = std::max(0, static_cast<int>(std::floor(p0)) >> kBlockBits);
      to[a] = std::min(L.blocks[a] - 1, static_cast<int>(std::ceil(p1)) >> kBlockBits);
    }
    for (int k = from[2]; k <= to[2]; ++k)
      for (int j = from[1]; j <= to[1]; ++j)
        for (int i = from[0]; i <= to[0]; ++i)
          L.slotOf[static_cast<std::size_t>(i) +
                   static_cast<std::size_t>(L.blocks[0]) *
                       (static_cast<std::size_t>(j) + static_cast<std::size_t>(L.blocks[1]) * k)] =
              1;
  }
  std::int32_t slots = 0;
  for (std::size_t n = 0; n < L.slotOf.size(); ++n) {
    if (!L.slotOf[n]) {
      L.slotOf[n] = -1;
      continue;
    }
    L.slotOf[n] = slots++;
    const int i = static_cast<int>(n % L.blocks[0]);
    const int j = static_cast<int>(n / L.blocks[0] % L.blocks[1]);
    const int k = static_cast<int>(n / (static_cast<std::size_t>(L.blocks[0]) * L.blocks[1]));
    L.blockAt.push_back({i, j, k});
  }
  const std::size_t points = static_cast<std::size_t>(slots) * kBlockPoints;
  if (points > kMaxLatticePoints) {
    throw InputError("the mesh's lattice would need " + number(4.0 * points / 1e9) +
                     " GB at a cell of " + number(cellSize) + " m; give a larger --cell");
  }
  L.values.resize(points);
  parallelForDynamic(L.blockAt.size(), 1, [&](std::size_t s) {
    const std::array<int, 3> B = L.blockAt[s];
    float* out = L.values.data() + s * kBlockPoints;
    float xs[kBlock];
    for (int i = 0; i < kBlock; ++i) xs[i] = L.position(B[0] * kBlock + i, 0, 0).x();
    for (int k = 0; k < kBlock; ++k)
      for (int j = 0; j < kBlock; ++j) {
        const Vec3 row = L.position(0, B[1] * kBlock + j, B[2] * kBlock + k);
        field.densityAlongX(xs, kBlock, row.y(), row.z(), out + localPoint(0, j, k));
      }
  });
  return L;
}

constexpr int kStep[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

}  // namespace

SurfaceMesh extractSurface(const splat::DensityField& field, float SD, float cellSize,
                           MeshStats* stats) {
  SurfaceMesh mesh;
  MeshStats local;
  MeshStats& st = stats ? *stats : local;
  st = MeshStats{};
  if (field.size() == 0) return mesh;
  if (!(cellSize > 0)) throw std::invalid_argument("extractSurface: cell size must be positive");
  auto t0 = Clock::now();
  const Lattice L = buildLattice(field, cellSize);
  const std::size_t blocks = L.blockAt.size();
  st.blocks = blocks;
  st.latticePoints = blocks * kBlockPoints;
  st.timings.lattice = since(t0);

  // Blocks that can hold part of the surface: the points of a block and of the blocks after it
  // (+x, +y, +z, which its cells and edges reach into) are not all on one side of SD. Deep
  // water and empty air are skipped by the two passes below.
  t0 = Clock::now();
  std::vector<std::uint8_t> side(blocks);  // 0 all below SD, 1 all at or above, 2 both
  parallelFor(blocks, [&](std::size_t b) {
    const float* v = L.values.data() + b * kBlockPoints;
    const auto [lo, hi] = std::minmax_element(v, v + kBlockPoints);
    side[b] = *hi < SD ? 0 : *lo >= SD ? 1 : 2;
  });
  std::vector<std::uint8_t> surface(blocks);
  parallelFor(blocks, [&](std::size_t b) {
    const std::array<int, 3> B = L.blockAt[b];
    const int own = side[b];
    bool mixed = own == 2;
    for (int n = 1; n < 8 && !mixed; ++n) {
      const std::int32_t other = L.slot((B[0] + (n & 1)) * kBlock, (B[1] + (n >> 1 & 1)) * kBlock,
                                        (B[2] + (n >> 2 & 1)) * kBlock);
      mixed = (other < 0 ? 0 : side[static_cast<std::size_t>(other)]) != own;
    }
    surface[b] = mixed;
  });
  st.surfaceBlocks = static_cast<std::size_t>(std::count(surface.begin(), surface.end(), 1));
  st.timings.lattice += since(t0);

  // Vertices: one per lattice edge whose ends lie on both sides of SD, owned by the block of
  // the edge's lower end; listed per block in local edge order (point * 3 + axis).
  t0 = Clock::now();
  std::vector<std::vector<std::uint16_t>> crossings(blocks);
  parallelForDynamic(blocks, 4, [&](std::size_t s) {
    if (!surface[s]) return;
    const std::array<int, 3> B = L.blockAt[s];
    const float* v = L.values.data() + s * kBlockPoints;
    for (int p = 0; p < kBlockPoints; ++p) {
      const int i = B[0] * kBlock + (p & 7), j = B[1] * kBlock + (p >> 3 & 7),
                k = B[2] * kBlock + (p >> 6);
      const bool inside = v[p] >= SD;
      for (int a = 0; a < 3; ++a) {
        if ((L.value(i + kStep[a][0], j + kStep[a][1], k + kStep[a][2]) >= SD) != inside)
          crossings[s].push_back(static_cast<std::uint16_t>(3 * p + a));
      }
    }
  });
  std::vector<std::uint32_t> firstVertex(blocks + 1, 0);
  for (std::size_t s = 0; s < blocks; ++s) {
    const std::size_t next = firstVertex[s] + crossings[s].size();
    if (next > std::numeric_limits<std::uint32_t>::max())
      throw InputError("the mesh would have more than 4 billion vertices; give a larger --cell");
    firstVertex[s + 1] = static_cast<std::uint32_t>(next);
  }
  mesh.positions.resize(3 * std::size_t{firstVertex[blocks]});
  mesh.normals.resize(mesh.positions.size());
  parallelForDynamic(blocks, 4, [&](std::size_t s) {
    const std::array<int, 3> B = L.blockAt[s];
    std::size_t n = firstVertex[s];
    for (const std::uint16_t edge : crossings[s]) {
      const int p = edge / 3, a = edge % 3;
      const int i = B[0] * kBlock + (p & 7), j = B[1] * kBlock + (p >> 3 & 7),
                k = B[2] * kBlock + (p >> 6);
      const float va = L.value(i, j, k);
      const float vb = L.value(i + kStep[a][0], j + kStep[a][1], k + kStep[a][2]);
      const float t = std::clamp((SD - va) / (vb - va), 0.0f, 1.0f);
      const Vec3 x = L.position(i + t * kStep[a][0], j + t * kStep[a][1], k + t * kStep[a][2]);
      float d;
      Vec3 gradC, gradD;
      field.densityAndGradients(x, d, gradC, gradD);
      Vec3 normal = -gradD;
      if (!(normal.norm() > 0)) normal = Vec3::Zero(), normal[a] = va > vb ? 1.0f : -1.0f;
      normal.normalize();
      for (int c = 0; c < 3; ++c)
        mesh.positions[3 * n + c] = x[c], mesh.normals[3 * n + c] = normal[c];
      ++n;
    }
  });
  st.timings.vertices = since(t0);

  // Triangles: each block's cells (lower corner in the block), from the case table.
  t0 = Clock::now();
  const CubeEdges& edges = cubeEdges();
  const std::array<CubeCase, 256>& cases = cubeCases();
  std::vector<std::vector<std::uint32_t>> triangles(blocks);
  parallelForDynamic(blocks, 4, [&](std::size_t s) {
    if (!surface[s]) return;
    const std::array<int, 3> B = L.blockAt[s];
    for (int p = 0; p < kBlockPoints; ++p) {
      const int i = B[0] * kBlock + (p & 7), j = B[1] * kBlock + (p >> 3 & 7),
                k = B[2] * kBlock + (p >> 6);
      int inside = 0;
      for (int c = 0; c < 8; ++c)
        inside |= (L.value(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1)) >= SD) << c;
      const CubeCase& cc = cases[inside];
      for (int n = 0; n < 3 * cc.count; ++n) {
        const int e = cc.edges[n], c = edges.corner[e];
        const int ci = i + (c & 1), cj = j + (c >> 1 & 1), ck = k + (c >> 2 & 1);
        const std::int32_t owner = L.slot(ci, cj, ck);
        const auto key = static_cast<std::uint16_t>(3 * localPoint(ci, cj, ck) + edges.axis[e]);
        const std::vector<std::uint16_t>& list = crossings[owner < 0 ? 0 : owner];
        const auto at = std::lower_bound(list.begin(), list.end(), key);
        if (owner < 0 || at == list.end() || *at != key)
          throw std::logic_error("marching cubes: a crossed edge without its vertex");
        triangles[s].push_back(firstVertex[owner] + static_cast<std::uint32_t>(at - list.begin()));
      }
    }
  });
  std::size_t total = 0;
  for (const auto& t : triangles) total += t.size();
  mesh.triangles.reserve(total);
  for (auto& t : triangles) {
    mesh.triangles.insert(mesh.triangles.end(), t.begin(), t.end());
    std::vector<std::uint32_t>().swap(t);
  }
  st.timings.triangles = since(t0);
  return mesh;
}

MeshCheck checkEdges(const SurfaceMesh& mesh) {
  // Directed edges (from, to); an undirected edge is a run of equal (min, max) keys.
  std::vector<std::uint64_t> directed;
  directed.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.triangles[t + k], b = mesh.triangles[t + (k + 1) % 3];
      directed.push_back(a << 32 | b);
    }
  std::vector<std::uint64_t> undirected(directed.size());
  for (std::size_t n = 0; n < directed.size(); ++n) {
    const std::uint64_t a = directed[n] >> 32, b = directed[n] & 0xffffffffu;
    undirected[n] = std::min(a, b) << 32 | std::max(a, b);
  }
  std::sort(directed.begin(), directed.end());
  std::sort(undirected.begin(), undirected.end());
  MeshCheck check;
  for (std::size_t n = 0; n < undirected.size();) {
    std::size_t m = n;
    while (m < undirected.size() && undirected[m] == undirected[n]) ++m;
    ++check.edges;
    if (m - n == 1) ++check.boundaryEdges;
    if (m - n > 2) ++check.nonManifoldEdges;
    n = m;
  }
  for (std::size_t n = 1; n < directed.size(); ++n)
    if (directed[n] == directed[n - 1]) ++check.misorientedEdges;
  return check;
}

namespace {
Vec3 vertexAt(const SurfaceMesh& m, std::uint32_t v) {
  return Vec3(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
}
}  // namespace

double surfaceArea(const SurfaceMesh& mesh) {
  double area = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const Vec3 a = vertexAt(mesh, mesh.triangles[t]), b = vertexAt(mesh, mesh.triangles[t + 1]),
               c = vertexAt(mesh, mesh.triangles[t + 2]);
    area += 0.5 * static_cast<double>((b - a).cross(c - a).norm());
  }
  return area;
}

double enclosedVolume(const SurfaceMesh& mesh) {
  double volume = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const Vec3 a = vertexAt(mesh, mesh.triangles[t]), b = vertexAt(mesh, mesh.triangles[t + 1]),
               c = vertexAt(mesh, mesh.triangles[t + 2]);
    volume += static_cast<double>(a.dot(b.cross(c))) / 6.0;
  }
  return volume;
}

}  // namespace sph::render::mesh
