// The observables shared by the validation tests and the sweeps (sim/run/Observables.h), on states
// small enough to work out by hand, and the EOS energy against a numerical integral of p / rho^2
// of the equation of state the solver runs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sim/solver/Kernels.h"
#include "sim/run/Observables.h"

namespace sph {
namespace {

Particles threeParticles() {
  Particles p;
  p.append(Vec3(0.1f, 0.2f, 0.3f), Vec3(1, 0, 0), 0, 1000);
  p.append(Vec3(-0.5f, 1.0f, 0.0f), Vec3(0, -2, 0), 1, 1000);
  p.append(Vec3(0.4f, 0.0f, 0.0f), Vec3(0, 3, 4), 2, 1000);
  p.rho = {1010.0f, 990.0f, 1030.0f};
  return p;
}

TEST(Observables, FrontSpeedMomentumAndKineticEnergyByHand) {
  const Particles p = threeParticles();
  EXPECT_EQ(run::surgeFront(p), 0.4f);
  EXPECT_EQ(run::maxSpeed(p), 5.0f);
  EXPECT_EQ(run::momentum(p, 2.0), Vec3d(2, 2, 8));
  EXPECT_DOUBLE_EQ(run::kineticEnergy(p, 2.0), 1.0 + 4.0 + 25.0);
  // Heights along g = (0, -10, 0) above the level y = -1 (-x . g = -10).
  EXPECT_NEAR(run::potentialEnergy(p, 2.0, Vec3(0, -10, 0), -10.0),
              2.0 * 10 * ((0.2 + 1) + (1.0 + 1) + (0.0 + 1)), 1e-5);
  const Particles none;
  EXPECT_EQ(run::surgeFront(none), -std::numeric_limits<float>::max());
  EXPECT_EQ(run::maxSpeed(none), 0.0f);
  EXPECT_EQ(run::kineticEnergy(none, 1.0), 0.0);
}

TEST(Observables, DensityErrorCountsOnlyCompressionButDeviationBothWays) {
  const run::DensityError e = run::densityError(threeParticles(), 1000.0);
  EXPECT_NEAR(e.meanCompression, (0.01 + 0 + 0.03) / 3, 1e-12);
  EXPECT_NEAR(e.maxCompression, 0.03, 1e-12);
  EXPECT_NEAR(e.meanDeviation, (0.01 + 0.01 + 0.03) / 3, 1e-12);
  EXPECT_NEAR(e.meanDensity, 1010.0, 1e-9);
  EXPECT_EQ(e.maxDensity, 1030.0);
  EXPECT_EQ(run::densityError(Particles{}, 1000.0).meanCompression, 0.0);
}

TEST(Observables, WallLoadIsThePressurePairForceOnTheSensorsBoundaryParticles) {
  // Two fluid particles above two boundary particles of a floor (h = 0.02 m, m = 0.001 kg, c =
  // 1.05): one 0.01 m straight above b0, one 0.01 m above and 0.01 m across from b1 (and 0.01 m
  // across, 0.01 m up from b0; sqrt(2) 0.01 m from b0 and 0.01 sqrt(5) m from b1).
  Particles f;
  f.append(Vec3(0, 0.01f, 0), Vec3::Zero(), 0, 1000);
  f.append(Vec3(0.01f, 0.01f, 0), Vec3::Zero(), 1, 1000);
  f.rho = {1000.0f, 1000.0f};
  f.p = {2000.0f, 1000.0f};
  solver::BoundaryParticles b;
  b.x = {0.0f, 0.02f}, b.y = {0.0f, 0.0f}, b.z = {0.0f, 0.0f};
  const double h = 0.02, m = 0.001, c = 1.05;
  const float pb = 3e-4f;   // p_b / rho_b^2 of both
  const double tol = 1e-7;  // ~2e-6 of the forces: positions in float
  // |F| = c m^2 (p_i/rho_i^2 + p_b/rho_b^2) 45 / (pi h^6) (h - r)^2, along i -> b.
  auto pair = [&](double pi, double wall, double r) {
    return c * m * m * (pi / 1e6 + wall) * 45 / (solver::kPi * std::pow(h, 6)) * (h - r) * (h - r);
  };
  const double r0 = 0.01, r1 = 0.01 * std::sqrt(2.0), s2 = std::sqrt(2.0);
  const Aabb left{Vec3(-0.005f, -0.01f, -0.01f), Vec3(0.005f, 0.005f, 0.01f)};
  const Vec3d onB0 = run::wallLoad(f, b, {pb, pb}, left, m, h, c);
  // b0: straight down from particle 0, down and back (-x) from particle 1.
  EXPECT_NEAR(onB0.y(), -(pair(2000, pb, r0) + pair(1000, pb, r1) / s2), tol);
  EXPECT_NEAR(onB0.x(), -pair(1000, pb, r1) / s2, tol);
  EXPECT_NEAR(onB0.z(), 0, 1e-12);
  // b1 (0.02, 0, 0): particle 0 is 0.01 sqrt(5) > h away; particle 1 is r1 away, down and +x.
  const Aabb right{Vec3(0.015f, -0.01f, -0.01f), Vec3(0.025f, 0.005f, 0.01f)};
  const Vec3d onB1 = run::wallLoad(f, b, {pb, pb}, right, m, h, c);
  EXPECT_NEAR(onB1.x(), pair(1000, pb, r1) / s2, tol);
  EXPECT_NEAR(onB1.y(), -pair(1000, pb, r1) / s2, tol);
  // No wall pressure (DFSPH): only the fluid's p_i / rho_i^2; a box around both: their sum.
  const Vec3d both = run::wallLoad(f, b, {}, Aabb{Vec3::Constant(-1), Vec3::Constant(1)}, m, h, c);
  EXPECT_NEAR(both.y(), -(pair(2000, 0, r0) + 2 * pair(1000, 0, r1) / s2), tol);
  EXPECT_NEAR(both.x(), 0, 1e-12);
  EXPECT_EQ(run::wallLoad(Particles{}, b, {}, left, m, h, c), Vec3d::Zero());
}

// e(rho) = integral from rho0 to rho of p(r) / r^2 dr (per unit mass), by Simpson's rule.
double integratedEnergy(const scene::SolverParams& s, double B, double rho) {
  const double rho0 = s.restDensity;
  auto p = [&](double r) {
    const double v =
        s.eos == scene::EquationOfState::Tait ? B * (std::pow(r / rho0, 7) - 1) : B * (r - rho0);
    return s.clampNegativePressure ? std::max(v, 0.0) : v;
  };
  const int n = 2000;
  const double h = (rho - rho0) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double r = rho0 + i * h;
    sum += p(r) / (r * r) * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  return sum * h / 3;
}

TEST(Observables, ElasticEnergyIsTheIntegralOfTheEquationOfState) {
  for (const scene::EquationOfState eos :
       {scene::EquationOfState::Tait, scene::EquationOfState::Linear}) {
    for (const bool clamp : {true, false}) {
      scene::SolverParams s;
      s.eos = eos;
      s.clampNegativePressure = clamp;
      const double B = eos == scene::EquationOfState::Tait ? 1.2e5 : 400.0;
      for (const float rho : {960.0f, 1000.0f, 1004.0f, 1050.0f}) {
        Particles p;
        p.append(Vec3::Zero(), Vec3::Zero(), 0, rho);
        const double expected = 0.5 * integratedEnergy(s, B, rho);
        EXPECT_NEAR(run::elasticEnergy(p, s, 0.5, B), expected, 1e-9 + 1e-6 * std::abs(expected))
            << enumName(eos) << (clamp ? " clamped" : "") << ", rho " << rho;
      }
    }
  }
}

// A rest lattice whose top layer is at y = (layers - 0.5) dx: its cells end at layers * dx, and
// that is where the fill fraction falls to 1/2 (to a few hundredths of a spacing: the kernel sum
// of a half lattice is not exactly half the full one); one more layer raises it by one spacing;
// a column with no water reads the bottom of the search.
TEST(Observables, WaterLevelIsWhereTheRestLatticesCellsEnd) {
  const float dx = 0.01f, h = 0.02f;
  auto pool = [&](int layers) {
    Particles p;
    std::uint32_t id = 0;
    for (int i = 0; i < 20; ++i)
      for (int k = 0; k < 20; ++k)
        for (int j = 0; j < layers; ++j)
          p.append(Vec3((i + 0.5f) * dx, (j + 0.5f) * dx, (k + 0.5f) * dx), Vec3::Zero(), id++,
                   1000);
    return p;
  };
  Aabb columns;
  columns.lo = Vec3(0.05f, 0.01f, 0.05f), columns.hi = Vec3(0.15f, 0.2f, 0.15f);
  const double five = run::waterLevel(pool(5), columns, h, dx);
  const double six = run::waterLevel(pool(6), columns, h, dx);
  EXPECT_NEAR(five, 0.05, 0.05 * dx);
  EXPECT_NEAR(six - five, dx, 1e-3 * dx);
  EXPECT_EQ(run::waterLevel(Particles{}, columns, h, dx), columns.lo.y());
}

}  // namespace
}  // namespace sph
