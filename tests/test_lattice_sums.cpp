// The rest-lattice sums (sim/solver/LatticeSums.h) that calibrate the solver's density and pressure
// gradient and the renderer's density field: against a brute-force sum over a larger block in
// another order, against values worked out by hand at a support of 1.5 spacings, and against the
// integrals they approximate once the support holds many spacings.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/solver/LatticeSums.h"
#include "sim/Types.h"

namespace sph {
namespace {

constexpr float kDx = 0.013f;  // an arbitrary spacing, not 1, so scaling errors show

double fullKernel(const solver::Kernels& k, scene::DensityKernel kernel, double r) {
  return kernel == scene::DensityKernel::Spiky ? k.spiky(static_cast<float>(r))
                                               : k.poly6(static_cast<float>(r * r));
}

// Every lattice point of a block two spacings wider than the support on each side, c outermost,
// in long double: no reach computation to get wrong, a different summation order.
long double bruteForce(const solver::Kernels& k, scene::DensityKernel kernel, int maxLayer) {
  const int n = static_cast<int>(k.h / kDx) + 2;
  long double sum = 0;
  for (int c = -n; c <= n; ++c)
    for (int b = -n; b <= std::min(n, maxLayer); ++b)
      for (int a = -n; a <= n; ++a)
        sum += fullKernel(k, kernel, kDx * std::sqrt(static_cast<double>(a * a + b * b + c * c)));
  return sum;
}

class LatticeKernelSum : public ::testing::TestWithParam<scene::DensityKernel> {};

TEST_P(LatticeKernelSum, MatchesABruteForceSum) {
  for (const float support : {1.0f, 1.5f, 2.0f, 2.5f, 3.7f}) {
    const solver::Kernels k(support * kDx);
    for (const int layer : {solver::kAllLayers, 0, -1}) {
      const long double brute = bruteForce(k, GetParam(), layer);
      EXPECT_NEAR(latticeKernelSum(k, GetParam(), kDx, layer), static_cast<double>(brute),
                  1e-6 * static_cast<double>(brute))
          << "support " << support << " spacings, layers b <= " << layer;
    }
  }
}

// With many spacings in the support the sum is a quadrature of the kernel's unit integral:
// spacing^3 sum W -> 1 (8 spacings: spiky 1.0009, poly6 1.00001).
TEST_P(LatticeKernelSum, TendsToTheKernelIntegral) {
  const solver::Kernels wide(8.0f * kDx);
  EXPECT_NEAR(kDx * kDx * kDx * latticeKernelSum(wide, GetParam(), kDx), 1.0, 2e-3);
}

// At the scenes' default support of 2 spacings the spiky sum is 24% high (poly6 1%): why the
// solver normalises its density by the lattice sum (SceneSetup.h).
TEST(LatticeKernelSum, SpikyAtTwoSpacingsNeedsTheNormalisation) {
  const solver::Kernels k(2.0f * kDx);
  EXPECT_GT(kDx * kDx * kDx * latticeKernelSum(k, scene::DensityKernel::Spiky, kDx), 1.2);
}

INSTANTIATE_TEST_SUITE_P(DensityKernels, LatticeKernelSum,
                         ::testing::Values(scene::DensityKernel::Spiky,
                                           scene::DensityKernel::Poly6));

TEST(LatticeKernelSum, Poly6AtOneAndAHalfSpacingsByHand) {
  // h = 1.5 dx reaches the centre, the 6 face neighbours (r = dx) and the 12 edge neighbours
  // (r^2 = 2 dx^2); W = c (h^2 - r^2)^3 with h^2 = 2.25 dx^2.
  const solver::Kernels k(1.5f * kDx);
  const double c = 315.0 / (64.0 * solver::kPi * std::pow(1.5 * kDx, 9)), d6 = std::pow(kDx, 6);
  const double centre = std::pow(2.25, 3), face = std::pow(1.25, 3), edge = std::pow(0.25, 3);
  const double bulk = c * d6 * (centre + 6 * face + 12 * edge);
  EXPECT_NEAR(latticeKernelSum(k, scene::DensityKernel::Poly6, kDx), bulk, 1e-6 * bulk);
  // The top layer of a free surface (b <= 0): no face neighbour above, 4 fewer edges.
  const double surface = c * d6 * (centre + 5 * face + 8 * edge);
  EXPECT_NEAR(latticeKernelSum(k, scene::DensityKernel::Poly6, kDx, 0), surface, 1e-6 * surface);
}

TEST(LatticeKernelSum, SpikyAtOneAndAHalfSpacingsByHand) {
  const solver::Kernels k(1.5f * kDx);
  const double c = 15.0 / (solver::kPi * std::pow(1.5 * kDx, 6)), d3 = std::pow(kDx, 3);
  const double expected =
      c * d3 * (std::pow(1.5, 3) + 6 * std::pow(0.5, 3) + 12 * std::pow(1.5 - std::sqrt(2.0), 3));
  EXPECT_NEAR(latticeKernelSum(k, scene::DensityKernel::Spiky, kDx), expected, 1e-6 * expected);
}

TEST(LatticeGradientMoment, AtOneAndAHalfSpacingsByHand) {
  // K = V sum_j x_j^2 |gradW| / r_j = V sum_j x_j^2 (45 / (pi h^6)) (h - r_j)^2 / r_j over the
  // points with x_j != 0: 2 face neighbours (x = +-dx, r = dx) and 8 edge neighbours (x = +-dx,
  // r = sqrt(2) dx).
  const solver::Kernels k(1.5f * kDx);
  const double h = 1.5 * kDx, g = 45.0 / (solver::kPi * std::pow(h, 6)), volume = std::pow(kDx, 3);
  const double rEdge = std::sqrt(2.0) * kDx;
  const double expected =
      volume * g *
      (2 * kDx * kDx * std::pow(h - kDx, 2) / kDx + 8 * kDx * kDx * std::pow(h - rEdge, 2) / rEdge);
  EXPECT_NEAR(latticeGradientMoment(k, kDx, volume), expected, 1e-6 * expected);
}

TEST(LatticeGradientMoment, TendsToOneForAWideSupport) {
  // -integral of x dW/dx over space = integral of W = 1 (by parts); 8 spacings: 0.9998. At the
  // default 2 spacings it is 0.956: the SPH gradient is 4.4% weak there without the correction.
  const double volume = std::pow(kDx, 3);
  EXPECT_NEAR(latticeGradientMoment(solver::Kernels(8.0f * kDx), kDx, volume), 1.0, 1e-3);
  EXPECT_LT(latticeGradientMoment(solver::Kernels(2.0f * kDx), kDx, volume), 0.97);
}

// DFSPH's Jacobi eigenvalue (LatticeSums.h). With only the six nearest neighbours in the support,
// g_j = s e_j for the six unit offsets: |sum g sin(q . e)|^2 = 4 s^2 (sin^2 q_x + sin^2 q_y +
// sin^2 q_z), at most 12 s^2 at q = pi / (2 dx) on each axis, over sum |g|^2 = 6 s^2: 2.
TEST(LatticeJacobiEigenvalue, SixNeighboursGiveTwo) {
  EXPECT_NEAR(latticeJacobiEigenvalue(solver::Kernels(1.2f * kDx), kDx), 2.0, 1e-9);
}

// Against a search over [0, pi / dx]^3 at 96 intervals an axis, in numpy (2026-12-01): 2.8207
// at 2 spacings, 6.7249 at 3, 14.426 at 4. The function's coarser grid reads a little below.
TEST(LatticeJacobiEigenvalue, GrowsWithTheSupport) {
  const double expected[][2] = {{2.0, 2.8207}, {3.0, 6.7249}, {4.0, 14.426}};
  for (const auto& [support, lambda] : expected) {
    const double read = latticeJacobiEigenvalue(solver::Kernels(float(support) * kDx), kDx);
    EXPECT_LE(read, lambda * 1.0001) << support << " spacings";
    EXPECT_GE(read, lambda * 0.998) << support << " spacings";
  }
}

}  // namespace
}  // namespace sph
