// Properties every SPH kernel must have (STYLE.md rule 12): unit integral over its support, zero
// outside it, non-negative, antisymmetric gradient matching the derivative of W, and for the
// viscosity kernel a Laplacian matching the numerical Laplacian.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/Kernels.h"
#include "sim/Types.h"

namespace sph {
namespace {

// Each kernel: W and gradient as implemented (float), and a double-precision reference of W
// written from the formula in Kernels.h, for the finite differences (float W loses too many
// digits near r = h for a second difference).
struct Poly6 {
  static double W(const Kernels& k, double r) { return k.poly6(static_cast<float>(r * r)); }
  static double ref(double h, double r) {
    return r < h ? 315.0 / (64.0 * kPi * std::pow(h, 9)) * std::pow(h * h - r * r, 3) : 0.0;
  }
  static Vec3 grad(const Kernels& k, const Vec3& r) {
    return k.poly6GradScale(r.squaredNorm()) * r;
  }
};
struct Spiky {
  static double W(const Kernels& k, double r) { return k.spiky(static_cast<float>(r)); }
  static double ref(double h, double r) {
    return r < h ? 15.0 / (kPi * std::pow(h, 6)) * std::pow(h - r, 3) : 0.0;
  }
  static Vec3 grad(const Kernels& k, const Vec3& r) { return k.spikyGradScale(r.norm()) * r; }
};
struct Viscosity {
  static double W(const Kernels& k, double r) { return k.viscosity(static_cast<float>(r)); }
  static double ref(double h, double r) {
    if (r >= h || r <= 0) return 0.0;
    const double q = r / h;
    return 15.0 / (2 * kPi * h * h * h) * (-0.5 * q * q * q + q * q + 0.5 / q - 1.0);
  }
  // dW/dr = c (-3r^2/(2h^3) + 2r/h^2 - h/(2r^2)), along r/|r|.
  static Vec3 grad(const Kernels& k, const Vec3& r) {
    const float d = r.norm();
    if (d >= k.h || d == 0) return Vec3::Zero();
    const float h = k.h;
    const float dWdr =
        k.viscFactor * (-1.5f * d * d / (h * h * h) + 2 * d / (h * h) - h / (2 * d * d));
    return dWdr / d * r;
  }
};

template <class K>
class KernelTest : public ::testing::Test {};
using AllKernels = ::testing::Types<Poly6, Spiky, Viscosity>;
TYPED_TEST_SUITE(KernelTest, AllKernels);

constexpr float kH = 0.037f;  // an arbitrary support radius, not 1, so scaling errors show

TYPED_TEST(KernelTest, IntegratesToOneOverItsSupport) {
  const Kernels k(kH);
  // Simpson's rule of 4 pi r^2 W(r) over [0, h]; the viscosity kernel's 1/r singularity is
  // integrable and vanishes with the r^2 weight.
  const int n = 20000;
  const double dr = static_cast<double>(kH) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double r = i * dr;
    const double f = (i == 0 ? 0.0 : 4 * kPi * r * r * TypeParam::W(k, r));
    sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  EXPECT_NEAR(sum * dr / 3, 1.0, 1e-3);
}

TYPED_TEST(KernelTest, IsZeroOutsideTheSupportAndNonNegativeInside) {
  const Kernels k(kH);
  for (double q : {1.0, 1.0001, 1.5, 3.0}) {
    EXPECT_EQ(TypeParam::W(k, q * kH), 0.0) << "r/h = " << q;
    EXPECT_EQ(TypeParam::grad(k, Vec3(static_cast<float>(q * kH), 0, 0)), Vec3::Zero());
  }
  for (double q = 0.01; q < 1; q += 0.01) EXPECT_GE(TypeParam::W(k, q * kH), 0.0) << "r/h = " << q;
}

TYPED_TEST(KernelTest, MatchesItsFormula) {
  const Kernels k(kH);
  for (double q = 0.05; q < 0.99; q += 0.01) {
    const double ref = TypeParam::ref(kH, q * kH);
    EXPECT_NEAR(TypeParam::W(k, q * kH), ref,
                1e-5 * std::abs(ref) + 1e-6 * TypeParam::ref(kH, 0.5 * kH))
        << "r/h = " << q;
  }
}

TYPED_TEST(KernelTest, GradientIsAntisymmetricAndMatchesTheDerivative) {
  const Kernels k(kH);
  const Vec3 dirs[] = {Vec3(1, 0, 0), Vec3(0.3f, -0.8f, 0.52f).normalized(),
                       Vec3(-1, 1, 1).normalized()};
  for (const Vec3& d : dirs) {
    for (double q = 0.1; q < 0.99; q += 0.07) {
      const Vec3 r = static_cast<float>(q * kH) * d;
      const Vec3 g = TypeParam::grad(k, r);
      EXPECT_EQ(TypeParam::grad(k, -r), -g);  // bit-exact: momentum conservation relies on it
      // Central difference of the reference W along the direction.
      const double e = 1e-5 * kH;
      const double dWdr =
          (TypeParam::ref(kH, q * kH + e) - TypeParam::ref(kH, q * kH - e)) / (2 * e);
      EXPECT_NEAR(g.dot(d), dWdr, 1e-4 * std::abs(dWdr) + 1e-3) << "r/h = " << q;
    }
  }
}

TEST(ViscosityKernel, LaplacianMatchesTheNumericalLaplacian) {
  const Kernels k(kH);
  for (double q = 0.1; q < 0.95; q += 0.05) {
    // Radial Laplacian: W'' + 2 W' / r.
    const double r = q * kH, e = 1e-4 * kH;
    const double w0 = Viscosity::ref(kH, r), wp = Viscosity::ref(kH, r + e),
                 wm = Viscosity::ref(kH, r - e);
    const double lap = (wp - 2 * w0 + wm) / (e * e) + (wp - wm) / (e * r);
    EXPECT_NEAR(k.viscosityLaplacian(static_cast<float>(r)), lap, 1e-4 * std::abs(lap))
        << "r/h = " << q;
  }
  EXPECT_EQ(k.viscosityLaplacian(kH), 0.0f);
}

}  // namespace
}  // namespace sph
