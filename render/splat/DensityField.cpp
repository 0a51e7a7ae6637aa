#include "render/splat/DensityField.h"

#include <algorithm>
#include <cmath>

#include "sim/solver/LatticeSums.h"
#include "sim/Parallel.h"

namespace sph::render::splat {
namespace {

// The inner loops over one contiguous range [b, e) of sorted particles, written over raw
// restrict pointers with the kernel's branch-free shape (sim/solver/Kernels.h) so they vectorise (as
// lambdas over the members they compiled to scalar code: 2 ns per candidate).
float poly6Range(const float* __restrict x, const float* __restrict y, const float* __restrict z,
                 std::uint32_t b, std::uint32_t e, float px, float py, float pz,
                 solver::Poly6Shape poly6) {
  float s = 0;
#pragma omp simd reduction(+ : s)
  for (std::uint32_t j = b; j < e; ++j) {
    const float dx = px - x[j], dy = py - y[j], dz = pz - z[j];
    s += poly6(dx * dx + dy * dy + dz * dz);
  }
  return s;
}

struct GradientSums {
  float density = 0, gx = 0, gy = 0, gz = 0, dgx = 0, dgy = 0, dgz = 0;
};

void gradientRange(const float* __restrict x, const float* __restrict y, const float* __restrict z,
                   const float* __restrict inverseDensity, std::uint32_t b, std::uint32_t e,
                   float px, float py, float pz, solver::Poly6Shape poly6, GradientSums& out) {
  float s = 0, ax = 0, ay = 0, az = 0, bx = 0, by = 0, bz = 0;
#pragma omp simd reduction(+ : s, ax, ay, az, bx, by, bz)
  for (std::uint32_t j = b; j < e; ++j) {
    const float dx = px - x[j], dy = py - y[j], dz = pz - z[j];
    const float r2 = dx * dx + dy * dy + dz * dz;
    s += poly6(r2);
    // gradW = poly6GradFactor (h^2 - r^2)^2 r_vec; eq. (4) weights it by 1 / rho_j.
    const float w = poly6.gradient(r2);
    bx += w * dx, by += w * dy, bz += w * dz;
    const float wc = w * inverseDensity[j];
    ax += wc * dx, ay += wc * dy, az += wc * dz;
  }
  out.density += s, out.gx += ax, out.gy += ay, out.gz += az;
  out.dgx += bx, out.dgy += by, out.dgz += bz;
}

}  // namespace

DensityField::DensityField(const float* x, const float* y, const float* z, std::size_t n,
                           float spacing, float radius, float restDensity)
    : kernels_(radius * spacing), spacing_(spacing), restDensity_(restDensity) {
  const double bulk = latticeKernelSum(kernels_, scene::DensityKernel::Poly6, spacing);
  massNorm_ = static_cast<float>(restDensity / bulk);
  flatSurfaceFraction_ = static_cast<float>(
      latticeKernelSum(kernels_, scene::DensityKernel::Poly6, spacing, 0) / bulk);
  std::vector<std::uint32_t> order;
  grid_.build(x, y, z, n, kernels_.h, order);
  x_.resize(n), y_.resize(n), z_.resize(n);
  for (std::size_t s = 0; s < n; ++s) x_[s] = x[order[s]], y_[s] = y[order[s]], z_[s] = z[order[s]];
  density_.resize(n);
  inverseDensity_.resize(n);
  parallelFor(n, [&](std::size_t s) {
    density_[s] = density(Vec3(x_[s], y_[s], z_[s]));
    inverseDensity_[s] = 1.0f / density_[s];
  });
  double sum = 0;
  for (std::size_t s = 0; s < n; ++s) sum += density_[s];
  meanDensity_ = n ? static_cast<float>(sum / n) : 0.0f;
}

float DensityField::density(const Vec3& p) const {
  const solver::Poly6Shape poly6{kernels_.h2};
  const float *x = x_.data(), *y = y_.data(), *z = z_.data();
  float sum = 0;
  grid_.forEachNeighbourRange(grid_.cellOf(p.x(), p.y(), p.z()),
                              [&](std::uint32_t b, std::uint32_t e) {
                                sum += poly6Range(x, y, z, b, e, p.x(), p.y(), p.z(), poly6);
                              });
  return massNorm_ * kernels_.poly6Factor * sum;
}

void DensityField::densityAlongX(const float* xs, int count, float py, float pz, float* out) const {
  if (count <= 0) return;
  const float h2 = kernels_.h2, h = kernels_.h;
  const solver::Poly6Shape poly6{h2};
  const auto [xmin, xmax] = std::minmax_element(xs, xs + count);
  const float lo[3] = {*xmin - h, py - h, pz - h}, hi[3] = {*xmax + h, py + h, pz + h};
  // Candidates within h of the line: their x and squared distance from it, appended without a
  // branch (about half the cells' particles pass: a branch would mispredict on every other one).
  thread_local std::vector<float> cx, cr;
  std::size_t n = 0;
  const float *x = x_.data(), *y = y_.data(), *z = z_.data();
  grid_.forEachRangeInBox(lo, hi, [&](std::uint32_t b, std::uint32_t e) {
    if (cx.size() < n + (e - b)) cx.resize(2 * (n + (e - b))), cr.resize(cx.size());
    float* __restrict ox = cx.data();
    float* __restrict orr = cr.data();
    for (std::uint32_t j = b; j < e; ++j) {
      const float dy = py - y[j], dz = pz - z[j], r2 = dy * dy + dz * dz;
      ox[n] = x[j], orr[n] = r2;
      n += r2 < h2;
    }
  });
  const float* __restrict ax = cx.data();
  const float* __restrict ar = cr.data();
  for (int i = 0; i < count; ++i) {
    const float px = xs[i];
    float sum = 0;
#pragma omp simd reduction(+ : sum)
    for (std::size_t k = 0; k < n; ++k) {
      const float dx = px - ax[k];
      sum += poly6(dx * dx + ar[k]);
    }
    out[i] = massNorm_ * kernels_.poly6Factor * sum;
  }
}

void DensityField::densityAndGradients(const Vec3& p, float& density, Vec3& gradient,
                                       Vec3& densityGradient) const {
  const solver::Poly6Shape poly6{kernels_.h2};
  const float *x = x_.data(), *y = y_.data(), *z = z_.data(), *inv = inverseDensity_.data();
  GradientSums sums;
  grid_.forEachNeighbourRange(grid_.cellOf(p.x(), p.y(), p.z()),
                              [&](std::uint32_t b, std::uint32_t e) {
                                gradientRange(x, y, z, inv, b, e, p.x(), p.y(), p.z(), poly6, sums);
                              });
  density = massNorm_ * kernels_.poly6Factor * sums.density;
  const float g = massNorm_ * kernels_.poly6GradFactor;
  gradient = g * Vec3(sums.gx, sums.gy, sums.gz);
  densityGradient = g * Vec3(sums.dgx, sums.dgy, sums.dgz);
}

void DensityField::densityAndGradient(const Vec3& p, float& density, Vec3& gradient) const {
  Vec3 unused;
  densityAndGradients(p, density, gradient, unused);
}

Vec3 DensityField::gradient(const Vec3& p) const {
  float d;
  Vec3 g;
  densityAndGradient(p, d, g);
  return g;
}

}  // namespace sph::render::splat
