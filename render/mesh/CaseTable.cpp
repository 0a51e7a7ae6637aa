#include "render/mesh/CaseTable.h"

#include <algorithm>
#include <stdexcept>

namespace sph::render::mesh {
namespace {

struct P3 {
  float x, y, z;
};
P3 operator-(P3 a, P3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
P3 cross(P3 a, P3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
float dot(P3 a, P3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

P3 cornerPosition(int c) {
  return {static_cast<float>(c & 1), static_cast<float>(c >> 1 & 1),
          static_cast<float>(c >> 2 & 1)};
}

CubeEdges makeEdges() {
  CubeEdges e{};
  int n = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int c = 0; c < 8; ++c)
      if (!(c >> axis & 1))
        e.corner[n] = static_cast<std::uint8_t>(c), e.axis[n++] = static_cast<std::uint8_t>(axis);
  return e;
}

int edgeBetween(const CubeEdges& edges, int a, int b) {
  const int lower = a < b ? a : b, bit = a ^ b;
  for (int e = 0; e < 12; ++e)
    if (edges.corner[e] == lower && (1 << edges.axis[e]) == bit) return e;
  throw std::logic_error("marching cubes: corners " + std::to_string(a) + ", " + std::to_string(b) +
                         " share no edge");
}

CubeCase deriveCase(const CubeEdges& edges, int inside) {
  auto in = [&](int c) { return (inside >> c & 1) != 0; };
  // Neighbours of each crossed edge along the face segments (two per crossed edge).
  std::array<std::array<int, 2>, 12> next;
  std::array<int, 12> degree{};
  auto link = [&](int a, int b) {
    next[a][degree[a]++] = b;
    next[b][degree[b]++] = a;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const int base = side << axis;
      const std::array<int, 4> ring = {base, base | 1 << u, base | 1 << u | 1 << v, base | 1 << v};
      std::array<int, 4> crossed;  // edge from ring[k] to ring[k+1], or -1
      int count = 0;
      for (int k = 0; k < 4; ++k) {
        const int a = ring[k], b = ring[(k + 1) % 4];
        crossed[k] = in(a) != in(b) ? edgeBetween(edges, a, b) : -1;
        count += crossed[k] >= 0;
      }
      if (count == 2) {
        int first = -1;
        for (int k = 0; k < 4; ++k) {
          if (crossed[k] < 0) continue;
          if (first < 0)
            first = crossed[k];
          else
            link(first, crossed[k]);
        }
      } else if (count == 4) {
        // Ambiguous face: cut off each inside corner, joining the two edges that meet there.
        for (int k = 0; k < 4; ++k)
          if (in(ring[k])) link(crossed[(k + 3) % 4], crossed[k]);
      }
    }
  }
  CubeCase out;
  std::array<bool, 12> used{};
  for (int start = 0; start < 12; ++start) {
    if (degree[start] == 0 || used[start]) continue;
    if (degree[start] != 2) throw std::logic_error("marching cubes: an edge on one face only");
    std::vector<int> loop = {start};
    used[start] = true;
    for (int previous = -1, at = start;;) {
      const int step = next[at][0] != previous ? next[at][0] : next[at][1];
      if (step == start) break;
      used[step] = true;
      loop.push_back(step);
      previous = at, at = step;
    }
    // Wind the loop so its normal (Newell) points from the inside corners to the outside ones.
    P3 normal{0, 0, 0}, outward{0, 0, 0};
    std::vector<P3> points;
    for (int e : loop) {
      const int a = edges.corner[e], b = a | 1 << edges.axis[e];
      P3 mid = cornerPosition(a);
      (edges.axis[e] == 0 ? mid.x : edges.axis[e] == 1 ? mid.y : mid.z) += 0.5f;
      points.push_back(mid);
      const P3 towardsOutside =
          in(a) ? cornerPosition(b) - cornerPosition(a) : cornerPosition(a) - cornerPosition(b);
      outward = {outward.x + towardsOutside.x, outward.y + towardsOutside.y,
                 outward.z + towardsOutside.z};
    }
    for (std::size_t k = 0; k < points.size(); ++k) {
      const P3 c = cross(points[k], points[(k + 1) % points.size()]);
      normal = {normal.x + c.x, normal.y + c.y, normal.z + c.z};
    }
    const float facing = dot(normal, outward);
    if (facing == 0) throw std::logic_error("marching cubes: a loop with no outward side");
    if (facing < 0) std::reverse(loop.begin(), loop.end());
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
      out.edges[3 * out.count + 0] = static_cast<std::uint8_t>(loop[0]);
      out.edges[3 * out.count + 1] = static_cast<std::uint8_t>(loop[k]);
      out.edges[3 * out.count + 2] = static_cast<std::uint8_t>(loop[k + 1]);
      ++out.count;
    }
  }
  return out;
}

}  // namespace

const CubeEdges& cubeEdges() {
  static const CubeEdges edges = makeEdges();
  return edges;
}

const std::array<CubeCase, 256>& cubeCases() {
  static const std::array<CubeCase, 256> cases = [] {
    std::array<CubeCase, 256> table;
    for (int inside = 0; inside < 256; ++inside) table[inside] = deriveCase(cubeEdges(), inside);
    return table;
  }();
  return cases;
}

}  // namespace sph::render::mesh
