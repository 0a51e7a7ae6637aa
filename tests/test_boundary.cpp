// Walls: the signed distances of every shape, the boundary particle layout, and that no particle
// crosses a wall however fast it moves.
#include <gtest/gtest.h>

#include <random>

#include "sim/solver/Boundary.h"
#include "sim/run/Simulation.h"

namespace sph {
namespace {

scene::BoundaryShape tank() {
  scene::BoundaryShape t;
  t.kind = scene::BoundaryShape::Kind::Tank;
  t.lo = Vec3(0, 0, 0), t.hi = Vec3(1, 0.5f, 0.4f);
  return t;
}
scene::BoundaryShape cup() {
  scene::BoundaryShape c;
  c.kind = scene::BoundaryShape::Kind::Cup;
  c.centre = Vec3(0, 0, 0), c.radius = 0.05f, c.height = 0.1f;
  return c;
}

TEST(Solid, SignedDistancesOfEachShape) {
  const scene::Solid t(tank(), 0.02f);
  EXPECT_NEAR(t.distance(Vec3(0.5f, 0.2f, 0.2f)), 0.2f, 1e-6f);  // inside the tank: to the floor
  EXPECT_NEAR(t.distance(Vec3(-0.01f, 0.2f, 0.2f)), -0.01f, 1e-6f);  // inside the left wall
  EXPECT_NEAR(t.distance(Vec3(-0.05f, 0.2f, 0.2f)), 0.03f, 1e-6f);   // outside, beyond the wall
  EXPECT_GT(t.distance(Vec3(0.5f, 3.0f, 0.2f)), 0.0f);               // open top: far above is free

  const scene::Solid c(cup(), 0.01f);
  EXPECT_NEAR(c.distance(Vec3(0, 0.05f, 0)), 0.05f, 1e-6f);  // centre: to the inner wall/floor
  EXPECT_NEAR(c.distance(Vec3(0.055f, 0.05f, 0)), -0.005f, 1e-6f);  // in the wall
  EXPECT_NEAR(c.distance(Vec3(0, -0.004f, 0)), -0.004f, 1e-6f);     // in the floor
  EXPECT_GT(c.distance(Vec3(0.055f, 0.12f, 0)), 0.0f);              // above the rim

  scene::BoundaryShape sphere;
  sphere.kind = scene::BoundaryShape::Kind::Sphere;
  sphere.centre = Vec3(1, 1, 1), sphere.radius = 0.5f;
  EXPECT_NEAR(scene::Solid(sphere, 0.01f).distance(Vec3(1, 2, 1)), 0.5f, 1e-6f);
  scene::BoundaryShape plane;
  plane.kind = scene::BoundaryShape::Kind::Plane;
  plane.point = Vec3(0, 0.1f, 0), plane.normal = Vec3(0, 2, 0);
  EXPECT_NEAR(scene::Solid(plane, 0.01f).distance(Vec3(3, 0.05f, -2)), -0.05f, 1e-6f);
}

TEST(Boundary, TankSamplesContinueTheFluidLattice) {
  Aabb domain;
  domain.lo = Vec3(-1, -1, -1), domain.hi = Vec3(2, 2, 2);
  const std::vector<Vec3> s = solver::sampleBoundaryShape(tank(), domain, 0.1f, 2);
  // Every sample sits at a half-integer lattice position outside the interior, in 2 layers.
  for (const Vec3& p : s) {
    for (int a = 0; a < 3; ++a) {
      const float cells = p[a] / 0.1f - 0.5f;
      ASSERT_NEAR(cells, std::round(cells), 1e-4f) << p.transpose();
    }
    EXPECT_TRUE(p.x() < 0 || p.x() > 1 || p.y() < 0 || p.z() < 0 || p.z() > 0.4f) << p.transpose();
    EXPECT_LT(p.y(), 0.5f);  // no lid
  }
  // The 10x5x4-cell interior grown by 2 cells on every side but the open top (14 x 7 x 8 cells),
  // minus the interior itself.
  EXPECT_EQ(static_cast<int>(s.size()), 14 * 7 * 8 - 10 * 5 * 4);
}

// Fires particles at the walls of a container at speeds far beyond what the step allows, and
// checks none ends up inside a wall or outside the container.
void fireAtWalls(const scene::BoundaryShape& shape, const Vec3& inside, float speed) {
  scene::Scene scene;
  scene.solver.spacing = 0.005f;
  scene.boundaries.push_back(shape);
  scene.domain.lo = Vec3::Constant(-2), scene.domain.hi = Vec3::Constant(2);
  solver::Boundary boundary(scene.boundaries, scene.domain, 0.005f, 2, 0.01f);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    Vec3 dir(u(rng), u(rng), u(rng));
    dir.normalize();
    Vec3 v = speed * dir;
    Vec3 x = inside;
    for (int step = 0; step < 50; ++step) {  // several steps, sliding along walls
      const Vec3 old = x;
      x += 0.004f * v;  // moves ~ a wall thickness per step at this speed
      boundary.enforce(old, x, v);
      ASSERT_GE(boundary.distance(x), 0.0f) << "particle " << i << " step " << step;
    }
    // Below the rim it is still inside the container (it may leave through the open top).
    if (shape.kind == scene::BoundaryShape::Kind::Tank) {
      ASSERT_GE(x.y(), shape.lo.y());
      if (x.y() < shape.hi.y()) {
        ASSERT_TRUE(x.x() >= shape.lo.x() && x.x() <= shape.hi.x() && x.z() >= shape.lo.z() &&
                    x.z() <= shape.hi.z())
            << x.transpose();
      }
    } else {
      ASSERT_GE(x.y(), shape.centre.y());
      if (x.y() < shape.centre.y() + shape.height) {
        ASSERT_LE(std::hypot(x.x() - shape.centre.x(), x.z() - shape.centre.z()),
                  shape.radius + 1e-5f);
      }
    }
  }
}

TEST(Boundary, NoParticleCrossesATankWall) {
  fireAtWalls(tank(), Vec3(0.5f, 0.25f, 0.2f), 3.0f);
}
TEST(Boundary, NoParticleCrossesACupWall) {
  fireAtWalls(cup(), Vec3(0, 0.03f, 0), 3.0f);
}

}  // namespace
}  // namespace sph
