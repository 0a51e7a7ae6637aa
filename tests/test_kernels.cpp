// Properties every SPH kernel must have (STYLE.md rule 12): unit integral over its support, zero
// outside it, non-negative, antisymmetric gradient matching the derivative of W, and for the
// viscosity kernel a Laplacian matching the numerical Laplacian. Checked on the kernels as the
// neighbour loops evaluate them (the shapes of sim/solver/Kernels.h times their factors: SphPasses.cpp,
// render/splat/DensityField.cpp), and those against Kernels' full functions, which the lattice
// sums use.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/solver/Kernels.h"
#include "sim/Types.h"

namespace sph {
namespace {

// Each kernel: W and its gradient as the hot loops compute them, the full functions of Kernels,
// and a double-precision reference of W written from the formula in Kernels.h, for the finite
// differences (float W loses too many digits near r = h for a second difference).
struct Poly6 {
  // DensityField and the poly6 density pass: poly6Factor * (h^2 - r^2)^3.
  static double W(const solver::Kernels& k, double r) {
    return k.poly6Factor * solver::Poly6Shape{k.h2}(static_cast<float>(r * r));
  }
  static double full(const solver::Kernels& k, double r) {
    return k.poly6(static_cast<float>(r * r));
  }
  static double ref(double h, double r) {
    return r < h ? 315.0 / (64.0 * solver::kPi * std::pow(h, 9)) * std::pow(h * h - r * r, 3) : 0.0;
  }
  // DensityField's normals: poly6GradFactor * (h^2 - r^2)^2 * r.
  static Vec3 grad(const solver::Kernels& k, const Vec3& r) {
    return (k.poly6GradFactor * solver::Poly6Shape{k.h2}.gradient(r.squaredNorm())) * r;
  }
  static Vec3 fullGrad(const solver::Kernels& k, const Vec3& r) {
    return k.poly6GradScale(r.squaredNorm()) * r;
  }
};
struct Spiky {
  // The spiky density pass: spikyFactor * (h - r)^3.
  static double W(const solver::Kernels& k, double r) {
    return k.spikyFactor * solver::SpikyShape{k.h}(static_cast<float>(r * r));
  }
  static double full(const solver::Kernels& k, double r) { return k.spiky(static_cast<float>(r)); }
  static double ref(double h, double r) {
    return r < h ? 15.0 / (solver::kPi * std::pow(h, 6)) * std::pow(h - r, 3) : 0.0;
  }
  // The force pass: spikyGradFactor * hr^2 * invR * r, with the pair terms of SpikyPairShape.
  static Vec3 grad(const solver::Kernels& k, const Vec3& r) {
    const solver::SpikyPairShape s{k.h, k.h2};
    const float r2 = r.squaredNorm();
    const float invR = s.inverseDistance(r2);
    const float hr = s.hMinusR(r2, invR);
    return (k.spikyGradFactor * hr * hr * invR) * r;
  }
  static Vec3 fullGrad(const solver::Kernels& k, const Vec3& r) {
    return k.spikyGradScale(r.norm()) * r;
  }
};
struct Viscosity {
  // Not in a hot loop (only its Laplacian is, through SpikyPairShape): the full function.
  static double W(const solver::Kernels& k, double r) { return k.viscosity(static_cast<float>(r)); }
  static double full(const solver::Kernels& k, double r) { return W(k, r); }
  static double ref(double h, double r) {
    if (r >= h || r <= 0) return 0.0;
    const double q = r / h;
    return 15.0 / (2 * solver::kPi * h * h * h) * (-0.5 * q * q * q + q * q + 0.5 / q - 1.0);
  }
  // dW/dr = c (-3r^2/(2h^3) + 2r/h^2 - h/(2r^2)), along r/|r|.
  static Vec3 grad(const solver::Kernels& k, const Vec3& r) {
    const float d = r.norm();
    if (d >= k.h || d == 0) return Vec3::Zero();
    const float h = k.h;
    const float dWdr =
        k.viscFactor * (-1.5f * d * d / (h * h * h) + 2 * d / (h * h) - h / (2 * d * d));
    return dWdr / d * r;
  }
  static Vec3 fullGrad(const solver::Kernels& k, const Vec3& r) { return grad(k, r); }
};

template <class K>
class KernelTest : public ::testing::Test {};
using AllKernels = ::testing::Types<Poly6, Spiky, Viscosity>;
TYPED_TEST_SUITE(KernelTest, AllKernels);

constexpr float kH = 0.037f;  // an arbitrary support radius, not 1, so scaling errors show

TYPED_TEST(KernelTest, IntegratesToOneOverItsSupport) {
  const solver::Kernels k(kH);
  // Simpson's rule of 4 pi r^2 W(r) over [0, h]; the viscosity kernel's 1/r singularity is
  // integrable and vanishes with the r^2 weight.
  const int n = 20000;
  const double dr = static_cast<double>(kH) / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double r = i * dr;
    const double f = (i == 0 ? 0.0 : 4 * solver::kPi * r * r * TypeParam::W(k, r));
    sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  EXPECT_NEAR(sum * dr / 3, 1.0, 1e-3);
}

TYPED_TEST(KernelTest, IsZeroOutsideTheSupportAndNonNegativeInside) {
  const solver::Kernels k(kH);
  for (double q : {1.0, 1.0001, 1.5, 3.0}) {
    EXPECT_EQ(TypeParam::W(k, q * kH), 0.0) << "r/h = " << q;
    EXPECT_EQ(TypeParam::full(k, q * kH), 0.0) << "r/h = " << q;
    const Vec3 r(static_cast<float>(q * kH), 0, 0);
    EXPECT_EQ(TypeParam::grad(k, r), Vec3::Zero());
    EXPECT_EQ(TypeParam::fullGrad(k, r), Vec3::Zero());
  }
  for (double q = 0.01; q < 1; q += 0.01) EXPECT_GE(TypeParam::W(k, q * kH), 0.0) << "r/h = " << q;
}

TYPED_TEST(KernelTest, MatchesItsFormula) {
  const solver::Kernels k(kH);
  for (double q = 0.05; q < 0.99; q += 0.01) {
    const double ref = TypeParam::ref(kH, q * kH);
    const double tolerance = 1e-5 * std::abs(ref) + 1e-6 * TypeParam::ref(kH, 0.5 * kH);
    EXPECT_NEAR(TypeParam::W(k, q * kH), ref, tolerance) << "r/h = " << q;
    EXPECT_NEAR(TypeParam::full(k, q * kH), ref, tolerance) << "r/h = " << q;
  }
}

// The loops' form (shape, then factor) and the full function round differently: a few ulp, and
// near r = h the difference h - r (from sqrt(r^2), or r^2 / r in the force pass) loses digits to
// cancellation, about 6 ulp(r) / (h - r) relative in the cube or square of it. Within rounding of
// r = h the two may disagree on which side of the support a point is, where both are ~0.
TYPED_TEST(KernelTest, ShapeTimesFactorIsTheFullKernel) {
  const solver::Kernels k(kH);
  const Vec3 d = Vec3(0.3f, -0.8f, 0.52f).normalized();
  const double scaleW = 1e-9 * std::abs(TypeParam::full(k, 0.5 * kH));
  const double scaleG = 1e-9 * TypeParam::fullGrad(k, static_cast<float>(0.5 * kH) * d).norm();
  for (int i = 0; i < 120; ++i) {
    const double q = 0.01 * i;
    const double relative = 1e-6 + (q < 1 ? 4e-7 * q / (1 - q) : 0.0);
    const double full = TypeParam::full(k, q * kH);
    EXPECT_NEAR(TypeParam::W(k, q * kH), full, relative * std::abs(full) + scaleW) << "r/h = " << q;
    const Vec3 r = static_cast<float>(q * kH) * d;
    const Vec3 g = TypeParam::grad(k, r), fullG = TypeParam::fullGrad(k, r);
    EXPECT_LE((g - fullG).norm(), relative * fullG.norm() + scaleG) << "r/h = " << q;
  }
}

TYPED_TEST(KernelTest, GradientIsAntisymmetricAndMatchesTheDerivative) {
  const solver::Kernels k(kH);
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

TEST(SpikyPairShape, AnOverlappingPairHasNoDirectionAndNoForce) {
  const solver::Kernels k(kH);
  const solver::SpikyPairShape s{k.h, k.h2};
  EXPECT_EQ(s.inverseDistance(0.0f), 0.0f);
  EXPECT_EQ(s.hMinusR(0.0f, 0.0f), 0.0f);
  EXPECT_EQ(Spiky::grad(k, Vec3::Zero()), Vec3::Zero());
}

TEST(ViscosityKernel, LaplacianAsTheForcePassComputesItMatchesTheNumericalLaplacian) {
  const solver::Kernels k(kH);
  const solver::SpikyPairShape s{k.h, k.h2};
  for (double q = 0.1; q < 0.95; q += 0.05) {
    // Radial Laplacian: W'' + 2 W' / r.
    const double r = q * kH, e = 1e-4 * kH;
    const double w0 = Viscosity::ref(kH, r), wp = Viscosity::ref(kH, r + e),
                 wm = Viscosity::ref(kH, r - e);
    const double lap = (wp - 2 * w0 + wm) / (e * e) + (wp - wm) / (e * r);
    const float r2 = static_cast<float>(r * r);
    const float loop = k.viscLapFactor * s.hMinusR(r2, s.inverseDistance(r2));
    EXPECT_NEAR(loop, lap, 1e-4 * std::abs(lap)) << "r/h = " << q;
    EXPECT_NEAR(k.viscosityLaplacian(static_cast<float>(r)), lap, 1e-4 * std::abs(lap))
        << "r/h = " << q;
  }
  EXPECT_EQ(k.viscosityLaplacian(kH), 0.0f);
  EXPECT_EQ(s.hMinusR(kH * kH, s.inverseDistance(kH * kH)), 0.0f);
}

TEST(SpikyMomentShape, IsTheRadialMomentOfTheSpikyGradient) {
  // (x_j - x_i) . gradW(x_i - x_j) = -r . gradW(r) = -spikyGradFactor * moment(r^2).
  const solver::Kernels k(kH);
  const Vec3 d = Vec3(-0.2f, 0.9f, 0.4f).normalized();
  for (double q = 0.0; q < 1.2; q += 0.05) {
    const Vec3 r = static_cast<float>(q * kH) * d;
    const double expected = -r.dot(Spiky::fullGrad(k, r));
    const double moment = -k.spikyGradFactor * solver::SpikyMomentShape{k.h}(r.squaredNorm());
    EXPECT_NEAR(moment, expected, 1e-6 * std::abs(expected) + 1e-12) << "r/h = " << q;
    EXPECT_GE(moment, 0.0);
  }
}

TEST(WithDensityShape, HandsOutTheShapeAndFactorOfTheChosenKernel) {
  const solver::Kernels k(kH);
  for (const scene::DensityKernel kernel :
       {scene::DensityKernel::Spiky, scene::DensityKernel::Poly6}) {
    withDensityShape(kernel, k, [&](auto shape, float factor) {
      for (double q = 0.0; q < 1.1; q += 0.1) {
        const double r = q * kH;
        const double full =
            kernel == scene::DensityKernel::Spiky ? Spiky::full(k, r) : Poly6::full(k, r);
        EXPECT_NEAR(factor * shape(static_cast<float>(r * r)), full,
                    (1e-6 + 4e-7 * q / (1 - q)) * full)
            << "r/h = " << q;
      }
    });
  }
}

}  // namespace
}  // namespace sph
