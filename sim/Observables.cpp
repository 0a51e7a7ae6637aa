#include "sim/Observables.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "sim/Kernels.h"
#include "sim/LatticeSums.h"

namespace sph {

float surgeFront(const Particles& fluid) {
  float front = -std::numeric_limits<float>::max();
  for (float x : fluid.x) front = std::max(front, x);
  return front;
}

float maxSpeed(const Particles& fluid) {
  float v = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i) v = std::max(v, fluid.velocity(i).norm());
  return v;
}

Vec3d momentum(const Particles& fluid, double mass) {
  Vec3d m = Vec3d::Zero();
  for (std::size_t i = 0; i < fluid.size(); ++i) m += mass * fluid.velocity(i).cast<double>();
  return m;
}

double kineticEnergy(const Particles& fluid, double mass) {
  double e = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i) e += 0.5 * mass * fluid.velocity(i).squaredNorm();
  return e;
}

double potentialEnergy(const Particles& fluid, double mass, const Vec3& gravity, double floor) {
  double e = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i)
    e += mass * (-static_cast<double>(fluid.position(i).dot(gravity)) - floor);
  return e;
}

double elasticEnergy(const Particles& fluid, const SolverParams& s, double mass, double stiffness) {
  const double m = mass, rho0 = s.restDensity, B = stiffness;
  double e = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const double rho = fluid.rho[i];
    if (rho <= rho0 && s.clampNegativePressure) continue;  // p = 0 stores nothing
    if (s.eos == EquationOfState::Tait) {
      // p = B ((rho/rho0)^7 - 1): e = B ((rho^6 - rho0^6) / (6 rho0^7) + 1/rho - 1/rho0).
      e += m * B *
           ((std::pow(rho, 6) - std::pow(rho0, 6)) / (6 * std::pow(rho0, 7)) + 1 / rho - 1 / rho0);
    } else {
      // p = k (rho - rho0): e = k (ln(rho/rho0) + rho0/rho - 1).
      e += m * B * (std::log(rho / rho0) + rho0 / rho - 1);
    }
  }
  return e;
}

LayerMean bottomLayer(const Particles& fluid, double top) {
  LayerMean m;
  double pressure = 0, height = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    if (fluid.y[i] < top) pressure += fluid.p[i], height += fluid.y[i], ++m.count;
  }
  if (m.count > 0) m.pressure = pressure / m.count, m.height = height / m.count;
  return m;
}

Vec3d wallLoad(const Particles& fluid, const BoundaryParticles& boundary,
               const std::vector<float>& boundaryPressureTerm, const Aabb& sensor, double mass,
               double h, double gradientCorrection) {
  // |gradW_spiky| = 45 / (pi h^6) (h - r)^2.
  const double scale = gradientCorrection * mass * mass * 45.0 / (kPi * std::pow(h, 6));
  // The fluid within reach of the sensor, binned in cells of side h over its bounding box.
  const float reachH = static_cast<float>(h);
  const Aabb reach{sensor.lo - Vec3::Constant(reachH), sensor.hi + Vec3::Constant(reachH)};
  std::vector<std::uint32_t> near;
  Aabb box{Vec3::Constant(std::numeric_limits<float>::max()),
           Vec3::Constant(-std::numeric_limits<float>::max())};
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    if (!reach.contains(fluid.position(i))) continue;
    near.push_back(static_cast<std::uint32_t>(i));
    box.grow(fluid.position(i));
  }
  if (near.empty()) return Vec3d::Zero();
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) dims[a] = static_cast<int>((box.hi[a] - box.lo[a]) / h) + 1;
  auto cellOf = [&](const Vec3& x, int a) {
    return static_cast<int>(std::floor((x[a] - box.lo[a]) / h));
  };
  auto index = [&](int cx, int cy, int cz) {
    return (static_cast<std::size_t>(cz) * dims[1] + cy) * dims[0] + cx;
  };
  std::vector<std::uint32_t> start(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2] + 1, 0);
  for (std::uint32_t i : near) {
    const Vec3 x = fluid.position(i);
    ++start[index(cellOf(x, 0), cellOf(x, 1), cellOf(x, 2)) + 1];
  }
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<std::uint32_t> sorted(near.size()), fill(start.begin(), start.end() - 1);
  for (std::uint32_t i : near) {
    const Vec3 x = fluid.position(i);
    sorted[fill[index(cellOf(x, 0), cellOf(x, 1), cellOf(x, 2))]++] = i;
  }
  Vec3d force = Vec3d::Zero();
  for (std::size_t b = 0; b < boundary.size(); ++b) {
    const Vec3 xbf(boundary.x[b], boundary.y[b], boundary.z[b]);
    if (!sensor.contains(xbf)) continue;
    const Vec3d xb = xbf.cast<double>();
    const double pb = boundaryPressureTerm.empty() ? 0.0 : boundaryPressureTerm[b];
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(cellOf(xbf, a) - 1, 0), hi[a] = std::min(cellOf(xbf, a) + 1, dims[a] - 1);
    }
    for (int cz = lo[2]; cz <= hi[2]; ++cz)
      for (int cy = lo[1]; cy <= hi[1]; ++cy)
        for (int cx = lo[0]; cx <= hi[0]; ++cx) {
          const std::size_t c = index(cx, cy, cz);
          for (std::uint32_t q = start[c]; q < start[c + 1]; ++q) {
            const std::uint32_t i = sorted[q];
            const Vec3d d = xb - fluid.position(i).cast<double>();  // from i towards b
            const double r = d.norm();
            if (r <= 0 || r >= h) continue;
            const double rho = fluid.rho[i];
            force += scale * (fluid.p[i] / (rho * rho) + pb) * (h - r) * (h - r) / r * d;
          }
        }
  }
  return force;
}

DensityError densityError(const Particles& fluid, double rho0) {
  DensityError d;
  if (fluid.empty()) return d;
  double compression = 0, deviation = 0, sum = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const double c = std::max(0.0, (fluid.rho[i] - rho0) / rho0);
    compression += c, d.maxCompression = std::max(d.maxCompression, c);
    deviation += std::abs(fluid.rho[i] - rho0) / rho0;
    const double rho = fluid.rho[i];
    sum += rho, d.maxDensity = std::max(d.maxDensity, rho);
  }
  const double n = static_cast<double>(fluid.size());
  d.meanCompression = compression / n;
  d.meanDeviation = deviation / n;
  d.meanDensity = sum / n;
  return d;
}

double waterLevel(const Particles& fluid, const Aabb& columns, float h, float dx, int n) {
  const Kernels k(h);
  const double lattice = latticeKernelSum(k, DensityKernel::Poly6, dx);
  double sum = 0;
  std::vector<Vec3> near;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const float x = columns.lo.x() + (a + 0.5f) / n * (columns.hi.x() - columns.lo.x());
      const float z = columns.lo.z() + (b + 0.5f) / n * (columns.hi.z() - columns.lo.z());
      near.clear();  // the particles within h of the line
      for (std::size_t i = 0; i < fluid.size(); ++i) {
        const float dxl = fluid.x[i] - x, dzl = fluid.z[i] - z;
        if (dxl * dxl + dzl * dzl < k.h2) near.push_back(fluid.position(i));
      }
      auto phi = [&](float y) {
        double s = 0;
        for (const Vec3& p : near) s += k.poly6((p - Vec3(x, y, z)).squaredNorm());
        return s / lattice;
      };
      float lo = columns.lo.y(), hi = columns.hi.y();
      if (phi(lo) < 0.5) {
        sum += lo;
        continue;
      }
      for (int it = 0; it < 40 && hi - lo > 1e-6f * dx; ++it) {
        const float mid = 0.5f * (lo + hi);
        (phi(mid) >= 0.5 ? lo : hi) = mid;
      }
      sum += 0.5 * (lo + hi);
    }
  }
  return sum / (n * n);
}

}  // namespace sph
