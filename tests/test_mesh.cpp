// The renderer's SD iso-surface as a mesh (render/mesh): the derived case table, a closed mesh of a
// ball of particles with the sphere's area and volume, outward normals that agree with the
// triangles and the density gradient, the silhouette and normals against the reference
// ray-marcher's picture of the same field, and the same mesh for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "render/mesh/CaseTable.h"
#include "render/mesh/SurfaceMesh.h"
#include "render/splat/DensityField.h"
#include "render/splat/ReferenceRaymarcher.h"
#include "render/splat/SplatBuilder.h"
#include "sim/Parallel.h"
#include "sim/scene/Camera.h"

namespace sph::render::mesh {
namespace {

constexpr float kSpacing = 0.01f;

struct Cloud {
  std::vector<float> x, y, z;
  void add(const Vec3& p) { x.push_back(p.x()), y.push_back(p.y()), z.push_back(p.z()); }
  splat::DensityField field() const {
    return splat::DensityField(x.data(), y.data(), z.data(), x.size(), kSpacing, 2.5f);
  }
};

// Lattice points within `radius` of `centre`.
void addBall(Cloud& c, const Vec3& centre, float radius) {
  const int n = static_cast<int>(std::ceil(radius / kSpacing));
  for (int k = -n; k <= n; ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const Vec3 d =
            kSpacing * Vec3(static_cast<float>(i), static_cast<float>(j), static_cast<float>(k));
        if (d.norm() <= radius) c.add(centre + d);
      }
}

Vec3 vertex(const SurfaceMesh& m, std::size_t v) {
  return Vec3(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
}
Vec3 normalOf(const SurfaceMesh& m, std::size_t v) {
  return Vec3(m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]);
}

// Where D crosses SD along a ray from `from` (inside) in direction `dir`, by bisection.
float isoDistance(const splat::DensityField& f, float SD, const Vec3& from, const Vec3& dir,
                  float reach) {
  float a = 0, b = reach;
  for (int it = 0; it < 60; ++it) {
    const float m = 0.5f * (a + b);
    (f.density(from + m * dir) >= SD ? a : b) = m;
  }
  return 0.5f * (a + b);
}

TEST(MeshCaseTable, EveryCaseIsClosedAndComplementsMatch) {
  const auto& cases = cubeCases();
  const CubeEdges& edges = cubeEdges();
  EXPECT_EQ(cases[0].count, 0);
  EXPECT_EQ(cases[255].count, 0);
  for (int inside = 0; inside < 256; ++inside) {
    const CubeCase& c = cases[inside];
    // The triangles use exactly the crossed edges, and their own edges inside the cube pair up:
    // each (edge a, edge b) side appears once in each direction, except the sides on the cube's
    // faces, which appear once (the neighbour cube closes them).
    std::array<int, 12> used{};
    for (int n = 0; n < 3 * c.count; ++n) used[c.edges[n]] = 1;
    for (int e = 0; e < 12; ++e) {
      const int a = edges.corner[e], b = a | 1 << edges.axis[e];
      const bool crossed = ((inside >> a) & 1) != ((inside >> b) & 1);
      EXPECT_EQ(used[e], crossed ? 1 : 0) << "case " << inside << " edge " << e;
    }
    // Complementary cases (inside <-> outside) have the same number of triangles unless a face
    // is ambiguous, where the rule picks the inside corners.
    EXPECT_LE(c.count, 12);
  }
  EXPECT_EQ(cases[1].count, 1);           // one corner: one triangle
  EXPECT_EQ(cases[3].count, 2);           // an edge: a quad
  EXPECT_EQ(cases[15].count, 2);          // a face: a quad
  EXPECT_EQ(cases[0b10000001].count, 2);  // corners 0 and 7, opposite: two corners cut off
}

class MeshOfBall : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    Cloud c;
    addBall(c, centre(), 12 * kSpacing);
    field_ = new splat::DensityField(c.field());
    SD_ = splat::surfaceDensity(*field_, 0);
    mesh_ = new SurfaceMesh(extractSurface(*field_, SD_, 0.5f * kSpacing));
    // The iso-surface's own radius, along 200 directions (a golden-angle spiral).
    double sum = 0;
    for (int n = 0; n < 200; ++n) {
      const double zc = 1 - (n + 0.5) / 100.0, r = std::sqrt(1 - zc * zc),
                   phi = n * 2.399963229728653;
      const Vec3 dir(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                     static_cast<float>(zc));
      sum += isoDistance(*field_, SD_, centre(), dir, 20 * kSpacing);
    }
    isoRadius_ = sum / 200;
  }
  static void TearDownTestSuite() { delete mesh_, delete field_; }
  static Vec3 centre() { return Vec3(0.3f, 0.2f, 0.1f); }
  static splat::DensityField* field_;
  static SurfaceMesh* mesh_;
  static float SD_;
  static double isoRadius_;
};
splat::DensityField* MeshOfBall::field_ = nullptr;
SurfaceMesh* MeshOfBall::mesh_ = nullptr;
float MeshOfBall::SD_ = 0;
double MeshOfBall::isoRadius_ = 0;

TEST_F(MeshOfBall, IsClosedOrientedAndASphereTopologically) {
  const MeshCheck check = checkEdges(*mesh_);
  EXPECT_GT(mesh_->triangleCount(), 5000u);
  EXPECT_EQ(check.boundaryEdges, 0u);
  EXPECT_EQ(check.nonManifoldEdges, 0u);
  EXPECT_EQ(check.misorientedEdges, 0u);
  EXPECT_TRUE(check.watertight());
  // Euler characteristic V - E + F = 2: one closed surface of genus 0.
  const long long chi = static_cast<long long>(mesh_->vertexCount()) -
                        static_cast<long long>(check.edges) +
                        static_cast<long long>(mesh_->triangleCount());
  EXPECT_EQ(chi, 2);
}

TEST_F(MeshOfBall, AreaAndVolumeAreTheSpheres) {
  // The particles reach 12 spacings; on a ball the automatic SD (set for a flat surface) lies
  // about a spacing inside the last layer.
  EXPECT_GT(isoRadius_, 10.5 * kSpacing);
  EXPECT_LT(isoRadius_, 13 * kSpacing);
  const double area = surfaceArea(*mesh_), volume = enclosedVolume(*mesh_);
  const double sphereArea = 4 * solver::kPi * isoRadius_ * isoRadius_;
  const double sphereVolume = 4.0 / 3.0 * solver::kPi * isoRadius_ * isoRadius_ * isoRadius_;
  EXPECT_NEAR(area / sphereArea, 1.0, 0.02) << area << " m^2 against " << sphereArea;
  EXPECT_NEAR(volume / sphereVolume, 1.0, 0.01) << volume << " m^3 against " << sphereVolume;
  // Every vertex lies on the iso-surface: D there within 2% of SD (linear interpolation on a
  // lattice edge), under 0.8% on average (0.52% measured).
  double mean = 0;
  double worst = 0;
  for (std::size_t v = 0; v < mesh_->vertexCount(); ++v) {
    const double e = std::abs(field_->density(vertex(*mesh_, v)) / SD_ - 1.0);
    worst = std::max(worst, e), mean += e;
  }
  EXPECT_LT(worst, 0.02);
  EXPECT_LT(mean / static_cast<double>(mesh_->vertexCount()), 0.008);
}

TEST_F(MeshOfBall, NormalsPointOutwardAlongTheGradientAndAgreeWithTheTriangles) {
  const SurfaceMesh& m = *mesh_;
  std::vector<Vec3> faceSum(m.vertexCount(), Vec3::Zero());
  for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
    const Vec3 a = vertex(m, m.triangles[t]), b = vertex(m, m.triangles[t + 1]),
               c = vertex(m, m.triangles[t + 2]);
    const Vec3 n = (b - a).cross(c - a);  // area-weighted, outward for a counter-clockwise winding
    for (int k = 0; k < 3; ++k) faceSum[m.triangles[t + k]] += n;
  }
  double meanRadial = 0, meanFace = 0, worstFace = 0, worstGradient = 0;
  for (std::size_t v = 0; v < m.vertexCount(); ++v) {
    const Vec3 n = normalOf(m, v), p = vertex(m, v);
    EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
    const double radial = n.dot((p - centre()).normalized());
    EXPECT_GT(radial, 0.8) << "vertex " << v;
    meanRadial += radial;
    const double face = std::acos(std::clamp<double>(n.dot(faceSum[v].normalized()), -1, 1));
    meanFace += face, worstFace = std::max(worstFace, face);
    float d;
    Vec3 gradC, gradD;
    field_->densityAndGradients(p, d, gradC, gradD);
    worstGradient = std::max<double>(worstGradient, (n + gradD.normalized()).norm());
  }
  const double count = static_cast<double>(m.vertexCount());
  EXPECT_GT(meanRadial / count, 0.99);
  EXPECT_LT(meanFace / count * 180 / solver::kPi, 5.0);  // degrees
  EXPECT_LT(worstFace * 180 / solver::kPi, 45.0);
  EXPECT_LT(worstGradient, 1e-4);  // -gradD, normalised
}

TEST(Mesh, SameMeshForAnyThreadCount) {
  Cloud c;
  addBall(c, Vec3(0, 0, 0), 7 * kSpacing);
  addBall(c, Vec3(0.16f, 0.02f, 0), 5 * kSpacing);
  const splat::DensityField field = c.field();
  const float SD = splat::surfaceDensity(field, 0);
  const int before = threadCount();
  setThreadCount(1);
  const SurfaceMesh one = extractSurface(field, SD, 0.4f * kSpacing);
  setThreadCount(3);
  const SurfaceMesh three = extractSurface(field, SD, 0.4f * kSpacing);
  setThreadCount(before);
  EXPECT_GT(one.triangleCount(), 1000u);
  EXPECT_EQ(one.positions, three.positions);
  EXPECT_EQ(one.normals, three.normals);
  EXPECT_EQ(one.triangles, three.triangles);
}

// A random cloud: clumps, filaments and loose particles of every density, so the iso-surface
// meets most of the 256 cases, ambiguous faces included. The mesh must still be closed.
TEST(Mesh, RandomCloudGivesAClosedMesh) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> u(0, 1);
  Cloud c;
  for (int blob = 0; blob < 30; ++blob) {
    const Vec3 centre(0.3f * u(random), 0.3f * u(random), 0.3f * u(random));
    const int count = 20 + static_cast<int>(200 * u(random));
    for (int n = 0; n < count; ++n)
      c.add(centre + 3 * kSpacing * Vec3(u(random) - 0.5f, u(random) - 0.5f, u(random) - 0.5f));
  }
  for (int n = 0; n < 500; ++n) c.add(0.3f * Vec3(u(random), u(random), u(random)));
  const splat::DensityField field = c.field();
  std::size_t triangles = 0;
  for (float threshold : {0.3f, 0.6f, 1.0f}) {
    const SurfaceMesh m = extractSurface(field, threshold * field.meanDensity(), 0.37f * kSpacing);
    const MeshCheck check = checkEdges(m);
    EXPECT_EQ(check.boundaryEdges, 0u) << threshold;
    EXPECT_EQ(check.nonManifoldEdges, 0u) << threshold;
    EXPECT_EQ(check.misorientedEdges, 0u) << threshold;
    EXPECT_GT(enclosedVolume(m), 0) << threshold;
    triangles += m.triangleCount();
  }
  EXPECT_GT(triangles, 10000u);
}

// The mesh drawn with the reference's camera covers the pixels the reference ray-marcher finds
// the surface in, and its normals there are the reference's.
struct Raster {
  std::vector<float> depth;
  std::vector<Vec3> normal, position;  // interpolated from the nearest triangle
};
Raster rasterise(const SurfaceMesh& m, const scene::CameraDesc& camera, int width, int height) {
  const scene::CameraBasis basis = scene::cameraBasis(camera);
  const Vec3 &eye = basis.eye, &forward = basis.forward, &right = basis.right, &up = basis.up;
  const float tanHalf = scene::tanHalfFovY(camera);
  const float aspect = static_cast<float>(width) / height;
  Raster r;
  r.depth.assign(static_cast<std::size_t>(width) * height, std::numeric_limits<float>::infinity());
  r.normal.assign(r.depth.size(), Vec3::Zero());
  r.position.assign(r.depth.size(), Vec3::Zero());
  auto project = [&](const Vec3& p, float& col, float& row, float& z) {
    const Vec3 d = p - eye;
    z = d.dot(forward);
    const float u = d.dot(right) / (z * tanHalf * aspect), v = d.dot(up) / (z * tanHalf);
    col = 0.5f * (u + 1) * width, row = 0.5f * (1 - v) * height;  // pixel centres at k + 0.5
  };
  for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
    float c[3], w[3], z[3];
    for (int k = 0; k < 3; ++k) project(vertex(m, m.triangles[t + k]), c[k], w[k], z[k]);
    const float area = (c[1] - c[0]) * (w[2] - w[0]) - (c[2] - c[0]) * (w[1] - w[0]);
    if (area == 0) continue;
    const int c0 = std::max(0, static_cast<int>(std::floor(std::min({c[0], c[1], c[2]}))));
    const int c1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({c[0], c[1], c[2]}))));
    const int r0 = std::max(0, static_cast<int>(std::floor(std::min({w[0], w[1], w[2]}))));
    const int r1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({w[0], w[1], w[2]}))));
    for (int row = r0; row <= r1; ++row)
      for (int col = c0; col <= c1; ++col) {
        const float px = col + 0.5f, py = row + 0.5f;
        float b[3];
        for (int k = 0; k < 3; ++k) {
          const int i = (k + 1) % 3, j = (k + 2) % 3;
          b[k] = ((c[j] - c[i]) * (py - w[i]) - (px - c[i]) * (w[j] - w[i])) / area;
        }
        if (b[0] < 0 || b[1] < 0 || b[2] < 0) continue;
        const float depth = b[0] * z[0] + b[1] * z[1] + b[2] * z[2];
        const std::size_t pixel = static_cast<std::size_t>(row) * width + col;
        if (depth >= r.depth[pixel]) continue;
        r.depth[pixel] = depth;
        Vec3 n = Vec3::Zero(), x = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
          n += b[k] * normalOf(m, m.triangles[t + k]);
          x += b[k] * vertex(m, m.triangles[t + k]);
        }
        r.normal[pixel] = n.normalized();
        r.position[pixel] = x;
      }
  }
  return r;
}

TEST(Mesh, SilhouetteAndNormalsMatchTheReferenceRaymarcher) {
  // A pool, a ball falling into it and a few loose particles (too thin to reach SD: in neither).
  Cloud c;
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 30; ++i)
        c.add(kSpacing * Vec3(static_cast<float>(i), static_cast<float>(j), static_cast<float>(k)));
  addBall(c, Vec3(0.12f, 0.16f, 0.06f), 5 * kSpacing);
  c.add(Vec3(0.25f, 0.2f, 0.05f));
  c.add(Vec3(0.27f, 0.22f, 0.02f));
  const splat::DensityField field = c.field();
  const float SD = splat::surfaceDensity(field, 0);
  const SurfaceMesh m = extractSurface(field, SD, 0.5f * kSpacing);
  scene::CameraDesc camera;
  camera.target = Vec3(0.15f, 0.08f, 0.06f);
  camera.position = camera.target + Vec3(0.25f, 0.2f, 0.35f);
  camera.fovYDegrees = 40;
  const int width = 160, height = 120;
  const frame::RenderImage reference =
      splat::raymarchReference(field, SD, camera, width, height, frame::Lighting{});
  const Raster r = rasterise(m, camera, width, height);
  std::size_t both = 0, either = 0, refCovered = 0;
  for (std::size_t p = 0; p < r.depth.size(); ++p) {
    const bool mesh = std::isfinite(r.depth[p]), ref = reference.covered[p] != 0;
    both += mesh && ref, either += mesh || ref, refCovered += ref;
  }
  ASSERT_GT(refCovered, 3000u);
  const double iou = static_cast<double>(both) / static_cast<double>(either);
  EXPECT_GT(iou, 0.97) << both << " of " << either << " pixels";
  // Where both cover a pixel they see the same point of the same surface: the reference's
  // normal there is -gradC (eq. (4), the renderer's shading normal) at the point the mesh has
  // under that pixel, and the mesh's normal is -gradD at it. (The two normals themselves differ
  // by the angle between gradC and gradD, ~12 deg on this pool's surface: the 1/rho_j weights.)
  double refAngle = 0, meshAngle = 0, between = 0;
  for (std::size_t p = 0; p < r.depth.size(); ++p) {
    if (!std::isfinite(r.depth[p]) || !reference.covered[p]) continue;
    const Vec3 ref =
        Vec3(reference.normal[3 * p], reference.normal[3 * p + 1], reference.normal[3 * p + 2])
            .normalized();
    float d;
    Vec3 gradC, gradD;
    field.densityAndGradients(r.position[p], d, gradC, gradD);
    auto angle = [](const Vec3& a, const Vec3& b) {
      return std::acos(std::clamp<double>(a.dot(b), -1, 1));
    };
    refAngle += angle(ref, -gradC.normalized());
    meshAngle += angle(r.normal[p], -gradD.normalized());
    between += angle(ref, r.normal[p]);
  }
  const double degrees = 180 / solver::kPi / static_cast<double>(both);
  EXPECT_LT(refAngle * degrees, 3.0);
  EXPECT_LT(meshAngle * degrees, 2.0);
  EXPECT_LT(between * degrees, 15.0);
  std::printf(
      "IoU %.4f; mean angles: reference vs -gradC at the mesh %.2f deg, mesh vs -gradD "
      "%.2f deg, mesh vs reference %.2f deg\n",
      iou, refAngle * degrees, meshAngle * degrees, between * degrees);
}

}  // namespace
}  // namespace sph::render::mesh
