// SPH smoothing kernels of Müller, Charypar & Gross 2003 (seed 003, eq. (3) for poly6), written
// for a support radius h: every kernel is zero for r >= h and integrates to 1 over the ball r < h.
//   poly6      W(r)   = 315/(64 pi h^9) (h^2 - r^2)^3          density (and the splat normals)
//   spiky      W(r)   = 15/(pi h^6) (h - r)^3                  its gradient: pressure force
//              gradW  = -45/(pi h^6) (h - r)^2 r/|r|
//   viscosity  W(r)   = 15/(2 pi h^3) (-r^3/(2h^3) + r^2/h^2 + h/(2r) - 1)
//              lapW   = 45/(pi h^6) (h - r)                     its Laplacian: viscosity force
// The constants are precomputed once per solver, so the hot loops do multiplies only.
//
// Two forms of each kernel live here. Kernels' member functions give the full value with a branch
// at the support (the lattice sums, SceneSetup.cpp, use them). The shapes below are what the
// neighbour loops run (sim/solver/SphPasses.cpp, render/splat/DensityField.cpp): the kernel divided by
// its constant factor, branch-free, so `omp simd` loops vectorise and the factor is applied once
// per particle. tests/test_kernels.cpp checks both against the formulas and against each other.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/scene/SolverParams.h"

namespace sph::solver {

constexpr double kPi = 3.14159265358979323846;

struct Kernels {
  float h = 0, h2 = 0;
  float poly6Factor = 0;      // 315/(64 pi h^9)
  float poly6GradFactor = 0;  // -6 * 315/(64 pi h^9): gradW = poly6GradFactor (h^2-r^2)^2 r_vec
  float spikyFactor = 0;      // 15/(pi h^6)
  float spikyGradFactor = 0;  // -45/(pi h^6)
  float viscFactor = 0;       // 15/(2 pi h^3)
  float viscLapFactor = 0;    // 45/(pi h^6)

  Kernels() = default;
  explicit Kernels(float supportRadius) {
    const double hd = supportRadius;
    h = supportRadius;
    h2 = supportRadius * supportRadius;
    poly6Factor = static_cast<float>(315.0 / (64.0 * kPi * std::pow(hd, 9)));
    poly6GradFactor = -6.0f * poly6Factor;
    spikyFactor = static_cast<float>(15.0 / (kPi * std::pow(hd, 6)));
    spikyGradFactor = static_cast<float>(-45.0 / (kPi * std::pow(hd, 6)));
    viscFactor = static_cast<float>(15.0 / (2.0 * kPi * std::pow(hd, 3)));
    viscLapFactor = static_cast<float>(45.0 / (kPi * std::pow(hd, 6)));
  }

  // --- poly6 ---
  float poly6(float r2) const {
    if (r2 >= h2) return 0.0f;
    const float d = h2 - r2;
    return poly6Factor * d * d * d;
  }
  // Gradient of poly6 along the vector r (= x_i - x_j) with |r|^2 = r2: scalar s, gradW = s * r.
  float poly6GradScale(float r2) const {
    if (r2 >= h2) return 0.0f;
    const float d = h2 - r2;
    return poly6GradFactor * d * d;
  }

  // --- spiky ---
  float spiky(float r) const {
    if (r >= h) return 0.0f;
    const float d = h - r;
    return spikyFactor * d * d * d;
  }
  // gradW = s * r_vec with s = spikyGradFactor (h - r)^2 / r; zero at r = 0 (no direction).
  float spikyGradScale(float r) const {
    if (r >= h || r <= 0.0f) return 0.0f;
    const float d = h - r;
    return spikyGradFactor * d * d / r;
  }

  // --- viscosity ---
  // Not used in a hot loop (only its Laplacian is); evaluated in double because the bracket
  // cancels to (1 - q)^3-small values near r = h.
  float viscosity(float r) const {
    if (r >= h || r <= 0.0f) return 0.0f;  // singular at r = 0, integrable
    const double q = static_cast<double>(r) / h;
    return static_cast<float>(viscFactor * (-0.5 * q * q * q + q * q + 0.5 / q - 1.0));
  }
  float viscosityLaplacian(float r) const {
    if (r >= h) return 0.0f;
    return viscLapFactor * (h - r);
  }
};

// ---- Shapes: the kernels as the neighbour loops evaluate them --------------------------------
// Functions of r^2 = |x_i - x_j|^2 with a clamp at 0 in place of `if (r >= h)`. Their operations
// and order are part of the results (runs are bit-reproducible, tests/test_determinism.cpp pins
// them): a change here is a change of results, not a refactoring.

// poly6: W = poly6Factor * Poly6Shape(r2); gradW = poly6GradFactor * gradient(r2) * (x_i - x_j).
struct Poly6Shape {
  float h2;
  float operator()(float r2) const {
    const float d = std::max(h2 - r2, 0.0f);
    return d * d * d;
  }
  float gradient(float r2) const {
    const float d = std::max(h2 - r2, 0.0f);
    return d * d;
  }
};

// spiky: W = spikyFactor * SpikyShape(r2).
struct SpikyShape {
  float h;
  float operator()(float r2) const {
    const float d = std::max(h - std::sqrt(r2), 0.0f);
    return d * d * d;
  }
};

// The pair terms of the force pass (Müller 2003): with hr = h - r and invR = 1 / r,
//   gradW_spiky(x_i - x_j) = spikyGradFactor * hr^2 * invR * (x_i - x_j)
//   lapW_visc(r)           = viscLapFactor * hr
// both zero outside the support and at r = 0 (a pair with no direction exerts no force).
struct SpikyPairShape {
  float h, h2;
  bool inside(float r2) const { return r2 < h2 && r2 > 0.0f; }
  float inverseDistance(float r2) const { return inside(r2) ? 1.0f / std::sqrt(r2) : 0.0f; }
  float hMinusR(float r2, float invR) const { return inside(r2) ? h - r2 * invR : 0.0f; }
};

// The radial moment of the spiky gradient, (h - r)^2 r = (x_j - x_i) . gradW(x_i - x_j) /
// (-spikyGradFactor): what the gradient correction sums (SphPasses.cpp, computeDensity).
struct SpikyMomentShape {
  float h;
  float operator()(float r2) const {
    const float r = std::sqrt(r2);
    const float hr = std::max(h - r, 0.0f);
    return hr * hr * r;
  }
};

// Calls f(shape, factor) with the shape of the solver's density kernel and the factor that makes
// it W (SolverParams.h: spiky by default, poly6 as in seed 003 eq. (3)).
template <class F>
void withDensityShape(scene::DensityKernel kernel, const Kernels& k, F&& f) {
  if (kernel == scene::DensityKernel::Spiky)
    f(SpikyShape{k.h}, k.spikyFactor);
  else
    f(Poly6Shape{k.h2}, k.poly6Factor);
}

}  // namespace sph::solver
