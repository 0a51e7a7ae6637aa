// SPH smoothing kernels of Müller, Charypar & Gross 2003 (seed 003, eq. (3) for poly6), written
// for a support radius h: every kernel is zero for r >= h and integrates to 1 over the ball r < h.
//   poly6      W(r)   = 315/(64 pi h^9) (h^2 - r^2)^3          density (and the splat normals)
//   spiky      W(r)   = 15/(pi h^6) (h - r)^3                  its gradient: pressure force
//              gradW  = -45/(pi h^6) (h - r)^2 r/|r|
//   viscosity  W(r)   = 15/(2 pi h^3) (-r^3/(2h^3) + r^2/h^2 + h/(2r) - 1)
//              lapW   = 45/(pi h^6) (h - r)                     its Laplacian: viscosity force
// The constants are precomputed once per solver, so the hot loops do multiplies only.
#pragma once

#include <cmath>

namespace sph {

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

}  // namespace sph
