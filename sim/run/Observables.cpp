#include "sim/run/Observables.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sim/solver/Kernels.h"
#include "sim/solver/LatticeSums.h"
#include "sim/grid/NeighbourGrid.h"

namespace sph::run {

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

double elasticEnergy(const Particles& fluid, const scene::SolverParams& s, double mass,
                     double stiffness) {
  const double m = mass, rho0 = s.restDensity, B = stiffness;
  double e = 0;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const double rho = fluid.rho[i];
    if (rho <= rho0 && s.clampNegativePressure) continue;  // p = 0 stores nothing
    if (s.eos == scene::EquationOfState::Tait) {
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

Vec3d wallLoad(const Particles& fluid, const solver::BoundaryParticles& boundary,
               const std::vector<float>& boundaryPressureTerm, const Aabb& sensor, double mass,
               double h, double gradientCorrection) {
  // |gradW_spiky| = 45 / (pi h^6) (h - r)^2.
  const double scale = gradientCorrection * mass * mass * 45.0 / (solver::kPi * std::pow(h, 6));
  // The fluid within reach of the sensor, binned in cells of side h (the simulation's grid).
  const float reachH = static_cast<float>(h);
  const Aabb reach{sensor.lo - Vec3::Constant(reachH), sensor.hi + Vec3::Constant(reachH)};
  std::vector<std::uint32_t> near;
  std::vector<float> nx, ny, nz;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    if (!reach.contains(fluid.position(i))) continue;
    near.push_back(static_cast<std::uint32_t>(i));
    nx.push_back(fluid.x[i]), ny.push_back(fluid.y[i]), nz.push_back(fluid.z[i]);
  }
  if (near.empty()) return Vec3d::Zero();
  grid::NeighbourGrid grid;
  std::vector<std::uint32_t> order;
  // Cells no smaller than h (float h may round below it): the 3x3x3 around b hold all within h.
  grid.build(nx.data(), ny.data(), nz.data(), near.size(), reachH * (1 + 1e-6f), order,
             grid::NeighbourGrid::kExactCellSize);
  Vec3d force = Vec3d::Zero();
  for (std::size_t b = 0; b < boundary.size(); ++b) {
    const Vec3 xbf(boundary.x[b], boundary.y[b], boundary.z[b]);
    if (!sensor.contains(xbf)) continue;
    const Vec3d xb = xbf.cast<double>();
    const double pb = boundaryPressureTerm.empty() ? 0.0 : boundaryPressureTerm[b];
    grid.forEachNeighbourRange(
        grid.cellOf(xbf.x(), xbf.y(), xbf.z()), [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t q = begin; q < end; ++q) {
            const std::uint32_t i = near[order[q]];
            const Vec3d d = xb - fluid.position(i).cast<double>();  // i -> b
            const double r = d.norm();
            if (r <= 0 || r >= h) continue;
            const double rho = fluid.rho[i];
            force += scale * (fluid.p[i] / (rho * rho) + pb) * (h - r) * (h - r) / r * d;
          }
        });
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
  const solver::Kernels k(h);
  const double lattice = latticeKernelSum(k, scene::DensityKernel::Poly6, dx);
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

}  // namespace sph::run
